// The sampling feature's families in the adapter's exposition
// (docs/metrics.md): its drops, the store-and-forward spool, every channel,
// the dynamic channels.
#pragma once

#include "feature/feature_metrics.hpp"

namespace nclink::detail {

void add_sampling_metrics(PrometheusText& out, const FeatureMetricsInput& in);

}  // namespace nclink::detail
