#include "adapter/adapter_reload.hpp"

#include "transport/broker_settings.hpp"

namespace nclink::detail {

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

    const SamplingConfig& s = a.sampling;
    const SamplingConfig& t = b.sampling;
    key(s.enabled == t.enabled, "sampling.enabled");
    key(s.max_dynamic_channels == t.max_dynamic_channels, "sampling.max_dynamic_channels");
    key(s.push_channels == t.push_channels, "sampling.push_channels");
    key(s.qos == t.qos, "sampling.qos");
    key(s.channel_qos == t.channel_qos, "sampling.channel_qos");
    key(s.full_policy == t.full_policy, "sampling.full_policy");
    key(s.ring_periods == t.ring_periods, "sampling.ring_periods");
    key(s.ring_max_rows == t.ring_max_rows, "sampling.ring_max_rows");
    key(s.direct_reads == t.direct_reads, "sampling.direct_reads");
    key(s.rt_priority == t.rt_priority, "sampling.rt_priority");
    key(s.timer_slack_ns == t.timer_slack_ns, "sampling.timer_slack_ns");
    key(s.cpu == t.cpu, "sampling.cpu");
    key(s.slice_us == t.slice_us, "sampling.slice_us");
    key(s.overrun_log_interval == t.overrun_log_interval, "sampling.overrun_log_interval_ms");
    key(s.text_budget_bytes == t.text_budget_bytes, "sampling.text_budget_bytes");
    key(s.max_dtu_bytes == t.max_dtu_bytes, "sampling.max_dtu_bytes");
    key(s.stats_item == t.stats_item, "sampling.stats_item");
    key(s.spool_memory_bytes == t.spool_memory_bytes, "sampling.spool_memory_bytes");
    key(s.spool_disk_bytes == t.spool_disk_bytes, "sampling.spool_disk_bytes");

    key(a.events.max_events == b.events.max_events, "events.max_events");
    key(a.events.poll_interval == b.events.poll_interval, "events.poll_interval_ms");
    key(a.events.max_queued_values == b.events.max_queued_values, "events.max_queued_values");
    key(a.events.qos == b.events.qos, "events.qos");
    key(a.methods.max_running == b.methods.max_running, "methods.max_running");
    key(a.methods.status_period == b.methods.status_period, "methods.status_period_ms");
    key(a.methods.stop_grace == b.methods.stop_grace, "methods.stop_grace_ms");

    key(a.driver_plugin == b.driver_plugin, "driver.plugin");
    key(a.driver_config == b.driver_config, "driver.config");
    key(a.log_level == b.log_level, "log_level");
    return out;
}

}  // namespace nclink::detail
