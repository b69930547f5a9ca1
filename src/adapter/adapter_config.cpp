#include <nclink/adapter_config.hpp>

#include "core/config_common.hpp"
#include "transport/broker_config.hpp"
#include "adapter/adapter_features.hpp"

namespace nclink {
using core_detail::ConfigReader;

Result<AdapterConfig> adapter_config_from_json(const Json& json, AdapterConfig c) {
    if (!json.is_object())
        return make_error(ErrorCode::syntax_error,
                          "configuration: the file must hold a JSON object");  // pointer "": the whole document
    core_detail::ConfigReader top(json, "");

    if (const Json* broker = top.object("broker")) {
        if (!broker->is_object()) return top.fail(ErrorCode::value_type, "broker", "must be an object");
        core_detail::ConfigReader b(*broker, "broker.");
        NCLINK_TRY(transport_detail::read_broker_common(b, c));
        NCLINK_TRY(b.boolean("clean_session", c.clean_session));
        NCLINK_TRY(b.no_unknown_keys());
    }

    NCLINK_TRY(top.str("model", c.model_path));
    NCLINK_TRY(top.str("device", c.device_id));
    NCLINK_TRY(top.str("dev_uuid", c.dev_uuid));
    NCLINK_TRY(top.boolean("strict", c.strict));
    NCLINK_TRY(top.str("persistence_dir", c.persistence_dir));
    NCLINK_TRY(top.boolean("standard_typo_topics", c.standard_typo_topics));
    NCLINK_TRY(top.count("offline_buffer_bytes", c.offline_buffer_bytes));
    NCLINK_TRY(top.count("max_in_flight", c.max_in_flight));
    NCLINK_TRY(top.duration("dedup_window_ms", c.dedup_window));
    NCLINK_TRY(top.count("dedup_capacity", c.dedup_capacity));
    NCLINK_TRY(top.count("request_threads", c.request_threads));
    NCLINK_TRY(top.count("max_pending_requests", c.max_pending_requests));
    NCLINK_TRY(top.count("max_request_bytes", c.max_request_bytes));
    NCLINK_TRY(top.duration("driver_timeout_ms", c.driver_timeout));
    NCLINK_TRY(top.duration("register_timeout_ms", c.register_timeout));
    NCLINK_TRY(top.duration("register_retry_max_ms", c.register_retry_max));
    NCLINK_TRY(top.duration("application_lease_ms", c.application_lease));
    NCLINK_TRY(top.count("heap_keep_bytes", c.heap_keep_bytes));
    NCLINK_TRY(adapter_detail::read_feature_sections(top, c));  // "sampling", "events", "methods"

    NCLINK_TRY(core_detail::read_log_level(top, c.log_level));
    NCLINK_TRY(core_detail::read_http_limits(top, "metrics", c.metrics));

    if (const Json* driver = top.object("driver")) {
        if (!driver->is_object()) return top.fail(ErrorCode::value_type, "driver", "must be an object");
        core_detail::ConfigReader d(*driver, "driver.");
        NCLINK_TRY(d.str("plugin", c.driver_plugin));
        if (const Json* config = d.object("config")) c.driver_config = *config;
        NCLINK_TRY(d.no_unknown_keys());
    }
    NCLINK_TRY(top.no_unknown_keys());
    if (c.request_threads == 0) c.request_threads = 1;
    if (c.max_in_flight == 0) c.max_in_flight = 1;
    return c;
}

Result<AdapterConfig> load_adapter_config(const std::string& path, AdapterConfig base) {
    auto doc = core_detail::read_config_document(path);
    if (!doc) return std::move(doc).error();
    auto config = adapter_config_from_json(doc->json, std::move(base));
    if (!config) return core_detail::located(*doc, std::move(config).error());
    const Json* json = &doc->json;
    AdapterConfig& c = config.value();
    if (json->contains("model")) core_detail::resolve_against(path, c.model_path);
    if (json->contains("persistence_dir")) core_detail::resolve_against(path, c.persistence_dir);
    if (json->contains("driver")) core_detail::resolve_against(path, c.driver_plugin);
    if (json->contains("broker")) transport_detail::resolve_tls_paths(path, c.tls);
    return config;
}

}  // namespace nclink
