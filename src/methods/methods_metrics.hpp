// The methods feature's families in the adapter's exposition (docs/metrics.md).
#pragma once

#include "feature/feature_metrics.hpp"

namespace nclink::detail {

void add_methods_metrics(PrometheusText& out, const FeatureMetricsInput& in);

}  // namespace nclink::detail
