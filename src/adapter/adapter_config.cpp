#include <nclink/adapter_config.hpp>

#include "core/config_reader.hpp"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace nclink {
using detail::ConfigReader;

std::optional<LogLevel> log_level_from_string(std::string_view text) {
    for (LogLevel level : {LogLevel::trace, LogLevel::debug, LogLevel::info, LogLevel::warn, LogLevel::error, LogLevel::off})
        if (to_string(level) == text) return level;
    if (text == "warning") return LogLevel::warn;
    return std::nullopt;
}

Result<AdapterConfig> adapter_config_from_json(const Json& json, AdapterConfig c) {
    if (!json.is_object()) return make_error(ErrorCode::syntax_error, "configuration: the file must hold a JSON object");
    ConfigReader top(json, "");

    if (const Json* broker = top.object("broker")) {
        if (!broker->is_object()) return make_error(ErrorCode::value_type, "configuration: broker must be an object");
        ConfigReader b(*broker, "broker.");
        NCLINK_TRY(b.str("url", c.broker_url));
        NCLINK_TRY(b.str("client_id", c.client_id));
        NCLINK_TRY(b.str("username", c.username));
        NCLINK_TRY(b.str("password", c.password));
        NCLINK_TRY(b.count("mqtt_version", c.mqtt_version));
        NCLINK_TRY(b.duration("keep_alive_s", c.keep_alive));
        NCLINK_TRY(b.boolean("clean_session", c.clean_session));
        if (const Json* tls = b.object("tls")) {
            if (!tls->is_object()) return make_error(ErrorCode::value_type, "configuration: broker.tls must be an object");
            ConfigReader t(*tls, "broker.tls.");
            MqttTlsOptions o = c.tls.value_or(MqttTlsOptions{});
            NCLINK_TRY(t.str("ca_file", o.ca_file));
            NCLINK_TRY(t.str("cert_file", o.cert_file));
            NCLINK_TRY(t.str("key_file", o.key_file));
            NCLINK_TRY(t.str("key_password", o.key_password));
            NCLINK_TRY(t.boolean("verify", o.verify_server));
            NCLINK_TRY(t.no_unknown_keys());
            c.tls = o;
        }
        NCLINK_TRY(b.no_unknown_keys());
        if (c.mqtt_version != 4 && c.mqtt_version != 5)
            return make_error(ErrorCode::value_type, "configuration: broker.mqtt_version must be 4 (MQTT 3.1.1) or 5");
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
    NCLINK_TRY(top.duration("driver_timeout_ms", c.driver_timeout));
    NCLINK_TRY(top.duration("register_timeout_ms", c.register_timeout));
    NCLINK_TRY(top.duration("register_retry_max_ms", c.register_retry_max));
    NCLINK_TRY(top.duration("application_lease_ms", c.application_lease));
    if (const Json* section = top.object("sampling")) NCLINK_TRY(detail::read_sampling_config(*section, c.sampling));
    if (const Json* section = top.object("events")) NCLINK_TRY(detail::read_events_config(*section, c.events));
    if (const Json* section = top.object("methods")) NCLINK_TRY(detail::read_methods_config(*section, c.methods));

    std::string level;
    NCLINK_TRY(top.str("log_level", level));
    if (!level.empty()) {
        auto parsed = log_level_from_string(level);
        if (!parsed)
            return make_error(ErrorCode::value_type,
                              fmt::format("configuration: log_level '{}' is not trace/debug/info/warn/error/off", level));
        c.log_level = *parsed;
    }

    if (const Json* driver = top.object("driver")) {
        if (!driver->is_object()) return make_error(ErrorCode::value_type, "configuration: driver must be an object");
        ConfigReader d(*driver, "driver.");
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
    std::ifstream in(path);
    if (!in) return make_error(ErrorCode::unavailable, fmt::format("cannot read configuration file {}", path));
    std::stringstream text;
    text << in.rdbuf();
    Json json = Json::parse(text.str(), nullptr, false);
    if (json.is_discarded())
        return make_error(ErrorCode::syntax_error, fmt::format("configuration file {} is not valid JSON", path));
    auto config = adapter_config_from_json(json, std::move(base));
    if (!config) return make_error(config.error().code, fmt::format("{}: {}", path, config.error().message));
    // Paths inside the file are relative to the file, not to where the program runs.
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    auto resolve = [&](std::string& p) {
        if (!p.empty() && std::filesystem::path(p).is_relative()) p = (dir / p).lexically_normal().string();
    };
    AdapterConfig& c = config.value();
    if (json.contains("model")) resolve(c.model_path);
    if (json.contains("persistence_dir")) resolve(c.persistence_dir);
    if (json.contains("driver")) resolve(c.driver_plugin);
    if (c.tls && json.contains("broker")) {
        resolve(c.tls->ca_file);
        resolve(c.tls->cert_file);
        resolve(c.tls->key_file);
    }
    return config;
}

}  // namespace nclink
