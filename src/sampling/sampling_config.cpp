#include "sampling/sampling_config.hpp"

#include "core/config_reader.hpp"

namespace nclink::sampling_detail {

Result<void> read_sampling_config(const Json& section, SamplingConfig& out) {
    core_detail::ConfigReader r(section, "sampling.");
    if (!section.is_object()) return r.fail(ErrorCode::value_type, "", "must be an object");
    NCLINK_TRY(r.boolean("enabled", out.enabled));
    NCLINK_TRY(r.count("max_dynamic_channels", out.max_dynamic_channels));
    NCLINK_TRY(r.read(
        "push_channels", out.push_channels,
        [](const Json& j) {
            if (!j.is_array()) return false;
            for (const auto& e : j)
                if (!e.is_string()) return false;
            return true;
        },
        "an array of channel ids"));
    const auto qos_value = [](const Json& j) {
        return j.is_number_integer() && (j.get<long long>() == 0 || j.get<long long>() == 1);
    };
    NCLINK_TRY(r.read("qos", out.qos, qos_value, "0 or 1"));
    NCLINK_TRY(r.read(
        "channel_qos", out.channel_qos,
        [&](const Json& j) {
            if (!j.is_object()) return false;
            for (const auto& q : j)
                if (!qos_value(q)) return false;
            return true;
        },
        "an object of channel id: 0 or 1"));
    NCLINK_TRY(r.str("full_policy", out.full_policy));
    if (out.full_policy != "drop_oldest" && out.full_policy != "block")
        return r.fail(ErrorCode::out_of_range, "full_policy", "must be \"drop_oldest\" or \"block\"");
    NCLINK_TRY(r.read(
        "ring_periods", out.ring_periods, [](const Json& j) { return j.is_number() && j.get<double>() > 0; },
        "a positive number"));
    NCLINK_TRY(r.count("ring_max_rows", out.ring_max_rows));
    NCLINK_TRY(r.read(
        "ring_min_ms", out.ring_min_ms,
        [](const Json& j) { return j.is_number() && j.get<double>() >= 0 && j.get<double>() <= 3.6e6; },
        "a number of milliseconds 0..3600000"));
    NCLINK_TRY(r.boolean("direct_reads", out.direct_reads));
    NCLINK_TRY(r.read(
        "rt_priority", out.rt_priority,
        [](const Json& j) { return j.is_number_integer() && j.get<long long>() >= 0 && j.get<long long>() <= 99; },
        "an integer 0..99"));
    NCLINK_TRY(r.count("timer_slack_ns", out.timer_slack_ns));
    NCLINK_TRY(r.read(
        "cpu", out.cpu, [](const Json& j) { return j.is_number_integer() && j.get<long long>() >= -1; }, "-1 or a CPU number"));
    NCLINK_TRY(r.read(
        "slice_us", out.slice_us,
        [](const Json& j) {
            if (!j.is_number_integer()) return false;
            const long long v = j.get<long long>();
            return v == 0 || (v >= 100 && v <= 100000);
        },
        "0 or an integer 100..100000"));
    NCLINK_TRY(r.duration("overrun_log_interval_ms", out.overrun_log_interval));
    NCLINK_TRY(r.count("text_budget_bytes", out.text_budget_bytes));
    NCLINK_TRY(r.count("max_dtu_bytes", out.max_dtu_bytes));
    NCLINK_TRY(r.str("stats_item", out.stats_item));
    NCLINK_TRY(r.count("spool_memory_bytes", out.spool_memory_bytes));
    NCLINK_TRY(r.count("spool_disk_bytes", out.spool_disk_bytes));
    return r.no_unknown_keys();
}

void sampling_config_changes(const SamplingConfig& s, const SamplingConfig& t, std::vector<std::string>& out) {
    const auto key = [&](bool same, const char* name) {
        if (!same) out.emplace_back(name);
    };
    key(s.enabled == t.enabled, "sampling.enabled");
    key(s.max_dynamic_channels == t.max_dynamic_channels, "sampling.max_dynamic_channels");
    key(s.push_channels == t.push_channels, "sampling.push_channels");
    key(s.qos == t.qos, "sampling.qos");
    key(s.channel_qos == t.channel_qos, "sampling.channel_qos");
    key(s.full_policy == t.full_policy, "sampling.full_policy");
    key(s.ring_periods == t.ring_periods, "sampling.ring_periods");
    key(s.ring_max_rows == t.ring_max_rows, "sampling.ring_max_rows");
    key(s.ring_min_ms == t.ring_min_ms, "sampling.ring_min_ms");
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
}

}  // namespace nclink::sampling_detail
