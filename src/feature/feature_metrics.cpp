// The features' shared pieces of the adapter's exposition (feature_metrics.hpp).
#include "feature/feature_metrics.hpp"

#include <algorithm>

namespace nclink::feature_detail {

void add_drop_metric(core_detail::PrometheusText& out, const core_detail::MetricLabels& device, const char* cause, std::uint64_t n) {
    core_detail::MetricLabels labels = device;
    labels.emplace_back("cause", cause);
    out.counter("nclink_adapter_drops_total",
                "Data lost, by cause: outbox_full (MQTT messages), ring_full (sample rows), spool_full (Sample DTUs), "
                "event_inbox_full (values notified for events)",
                labels, n);
}

std::uint64_t json_count(const Json& object, const char* key) {
    if (!object.is_object()) return 0;
    auto it = object.find(key);
    if (it == object.end() || !it->is_number()) return 0;
    return it->is_number_unsigned() ? it->get<std::uint64_t>() : static_cast<std::uint64_t>(std::max<double>(0, it->get<double>()));
}

const Json& json_member(const Json& object, const char* key) {
    static const Json none;
    if (!object.is_object()) return none;
    auto it = object.find(key);
    return it == object.end() ? none : *it;
}

}  // namespace nclink::feature_detail
