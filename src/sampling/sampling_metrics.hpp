// The sampling feature's families in the adapter's exposition
// (docs/metrics.md): its drops, the store-and-forward spool, every channel,
// the dynamic channels.
#pragma once

#include "feature/feature_metrics.hpp"

#include <nclink/sampling.hpp>

namespace nclink::sampling_detail {

/// `channels`: the sample channels (Adapter::sampling_stats()).
void add_sampling_metrics(core_detail::PrometheusText& out, const feature_detail::FeatureMetricsInput& in,
                          const SamplingStats& channels);

}  // namespace nclink::sampling_detail
