// The events feature's metrics (events_metrics.hpp).
#include "events/events_metrics.hpp"

namespace nclink::events_detail {

void add_events_metrics(core_detail::PrometheusText& out, const feature_detail::FeatureMetricsInput& in) {
    feature_detail::add_drop_metric(out, in.device, "event_inbox_full", feature_detail::json_count(in.stats, "dropped_values"));
    if (!in.stats.is_object()) return;
    out.gauge("nclink_adapter_events_registered", "Event registrations in place (8.2.27)", in.device,
              static_cast<double>(feature_detail::json_count(in.stats, "registered")));
    out.counter("nclink_adapter_events_fired_total", "Event DTUs triggered (8.2.31)", in.device,
                feature_detail::json_count(in.stats, "fired"));
}

}  // namespace nclink::events_detail
