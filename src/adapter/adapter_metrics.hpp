// The adapter's part of the Prometheus exposition (docs/metrics.md), from
// plain statistics, so tests can render known values.
#pragma once

#include "core/prometheus_text.hpp"

#include <nclink/adapter.hpp>
#include <nclink/sampling.hpp>
#include <nclink/traffic_stats.hpp>

#include <string>

namespace nclink::adapter_detail {

void add_adapter_metrics(core_detail::PrometheusText& out, const std::string& dev, const AdapterStats& stats,
                         const SamplingStats& sampling, const TrafficStats& traffic);

}  // namespace nclink::adapter_detail
