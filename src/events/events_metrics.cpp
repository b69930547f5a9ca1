// The events feature's metrics (events_metrics.hpp).
#include "events/events_metrics.hpp"

namespace nclink::detail {

void add_events_metrics(PrometheusText& out, const FeatureMetricsInput& in) {
    add_drop_metric(out, in.device, "event_inbox_full", json_count(in.stats, "dropped_values"));
    if (!in.stats.is_object()) return;
    out.gauge("nclink_adapter_events_registered", "Event registrations in place (8.2.27)", in.device,
              static_cast<double>(json_count(in.stats, "registered")));
    out.counter("nclink_adapter_events_fired_total", "Event DTUs triggered (8.2.31)", in.device, json_count(in.stats, "fired"));
}

}  // namespace nclink::detail
