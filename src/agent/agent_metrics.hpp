// The agent's part of the Prometheus exposition (docs/metrics.md), from
// plain statistics, so tests can render known values.
#pragma once

#include "core/prometheus_text.hpp"

#include <nclink/agent.hpp>
#include <nclink/traffic_stats.hpp>

#include <vector>

namespace nclink::agent_detail {

void add_agent_metrics(core_detail::PrometheusText& out, const AgentStats& stats, const std::vector<TerminalInfo>& terminals,
                       const TrafficStats& traffic);

}  // namespace nclink::agent_detail
