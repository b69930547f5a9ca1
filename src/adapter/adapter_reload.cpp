#include "adapter/adapter_reload.hpp"
#include "adapter/adapter_features.hpp"

#include "transport/broker_settings.hpp"

namespace nclink::adapter_detail {

std::vector<std::string> adapter_config_changes(const AdapterConfig& a, const AdapterConfig& b) {
    using transport_detail::BrokerSettings;
    std::vector<std::string> out = transport_detail::broker_reload_keys(BrokerSettings::of(a), BrokerSettings::of(b));
    auto key = [&](bool same, const char* name) {
        if (!same) out.emplace_back(name);
    };
    key(a.model_path == b.model_path, "model");
    key(a.device_id == b.device_id, "device");
    key(a.dev_uuid == b.dev_uuid, "dev_uuid");
    key(a.strict == b.strict, "strict");
    key(a.persistence_dir == b.persistence_dir, "persistence_dir");
    key(a.standard_typo_topics == b.standard_typo_topics, "standard_typo_topics");
    key(a.offline_buffer_bytes == b.offline_buffer_bytes, "offline_buffer_bytes");
    key(a.max_in_flight == b.max_in_flight, "max_in_flight");
    key(a.dedup_window == b.dedup_window, "dedup_window_ms");
    key(a.dedup_capacity == b.dedup_capacity, "dedup_capacity");
    key(a.request_threads == b.request_threads, "request_threads");
    key(a.max_pending_requests == b.max_pending_requests, "max_pending_requests");
    key(a.max_request_bytes == b.max_request_bytes, "max_request_bytes");
    key(a.driver_timeout == b.driver_timeout, "driver_timeout_ms");
    key(a.register_timeout == b.register_timeout, "register_timeout_ms");
    key(a.register_retry_max == b.register_retry_max, "register_retry_max_ms");
    key(a.application_lease == b.application_lease, "application_lease_ms");
    key(a.heap_keep_bytes == b.heap_keep_bytes, "heap_keep_bytes");

    feature_config_changes(a, b, out);  // each feature's own section (adapter_features.cpp)

    key(a.driver_plugin == b.driver_plugin, "driver.plugin");
    key(a.driver_config == b.driver_config, "driver.config");
    key(a.log_level == b.log_level, "log_level");
    key(a.metrics == b.metrics, "metrics");  // the program's /metrics server, bound once
    return out;
}

}  // namespace nclink::adapter_detail
