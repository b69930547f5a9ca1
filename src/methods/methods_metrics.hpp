// The methods feature's families in the adapter's exposition (docs/metrics.md).
#pragma once

#include "feature/feature_metrics.hpp"

namespace nclink::methods_detail {

void add_methods_metrics(core_detail::PrometheusText& out, const feature_detail::FeatureMetricsInput& in);

}  // namespace nclink::methods_detail
