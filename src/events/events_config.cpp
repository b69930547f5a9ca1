#include "events/events_config.hpp"

#include "core/config_reader.hpp"

namespace nclink::events_detail {

Result<void> read_events_config(const Json& section, EventsConfig& out) {
    core_detail::ConfigReader r(section, "events.");
    if (!section.is_object()) return r.fail(ErrorCode::value_type, "", "must be an object");
    NCLINK_TRY(r.count("max_events", out.max_events));
    NCLINK_TRY(r.duration("poll_interval_ms", out.poll_interval));
    NCLINK_TRY(r.count("max_queued_values", out.max_queued_values));
    NCLINK_TRY(r.read(
        "qos", out.qos,
        [](const Json& j) { return j.is_number_integer() && (j.get<long long>() == 0 || j.get<long long>() == 1); }, "0 or 1"));
    if (out.max_queued_values == 0) return r.fail(ErrorCode::out_of_range, "max_queued_values", "must be positive");
    return r.no_unknown_keys();
}

void events_config_changes(const EventsConfig& a, const EventsConfig& b, std::vector<std::string>& out) {
    const auto key = [&](bool same, const char* name) {
        if (!same) out.emplace_back(name);
    };
    key(a.max_events == b.max_events, "events.max_events");
    key(a.poll_interval == b.poll_interval, "events.poll_interval_ms");
    key(a.max_queued_values == b.max_queued_values, "events.max_queued_values");
    key(a.qos == b.qos, "events.qos");
}

}  // namespace nclink::events_detail
