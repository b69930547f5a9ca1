// The events feature's families in the adapter's exposition (docs/metrics.md).
#pragma once

#include "feature/feature_metrics.hpp"

namespace nclink::detail {

void add_events_metrics(PrometheusText& out, const FeatureMetricsInput& in);

}  // namespace nclink::detail
