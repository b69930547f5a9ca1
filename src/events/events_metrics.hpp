// The events feature's families in the adapter's exposition (docs/metrics.md).
#pragma once

#include "feature/feature_metrics.hpp"

namespace nclink::events_detail {

void add_events_metrics(core_detail::PrometheusText& out, const feature_detail::FeatureMetricsInput& in);

}  // namespace nclink::events_detail
