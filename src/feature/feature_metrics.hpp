// How a feature shows in the adapter's Prometheus exposition (docs/metrics.md):
// each feature's module writes its own families from what it reports, its
// object in AdapterStats::features (sampling also reads its channels), so the
// adapter's metrics name no feature. adapter_features.cpp lists the writers
// beside the features.
#pragma once

#include "core/prometheus_text.hpp"

#include <nclink/json.hpp>

#include <cstdint>

namespace nclink::feature_detail {

/// What a feature's metrics are written from: one statistics snapshot.
struct FeatureMetricsInput {
    const core_detail::MetricLabels& device;  ///< {"dev", <device>}
    const Json& stats;                        ///< the feature's object in AdapterStats::features; null when absent
};

/// One sample of the family every cause of lost data is counted in:
/// nclink_adapter_drops_total{cause=...}, each cause in its own unit.
void add_drop_metric(core_detail::PrometheusText& out, const core_detail::MetricLabels& device, const char* cause, std::uint64_t n);

/// A non-negative count at `key` of a JSON object; 0 when absent or not a number.
std::uint64_t json_count(const Json& object, const char* key);
/// The member `key` of a JSON object; null when absent.
const Json& json_member(const Json& object, const char* key);

}  // namespace nclink::feature_detail
