// The agent's statistics in the Prometheus text exposition format
// (docs/metrics.md): registrations, discovery answers, terminals by kind and
// state, forwarding timeouts and DEV_UNREACHABLE answers, DTUs in and out by
// kind, malformed DTUs. `nclink-agent --http HOST:PORT` serves it at /metrics.
//
// Thread-safe (reads the agent's thread-safe statistics).
#pragma once

#include <nclink/agent.hpp>
#include <nclink/export.hpp>

#include <string>

namespace nclink {

/// No label names the agent: the scrape target does (Prometheus adds `instance`).
NCLINK_API std::string prometheus_metrics(const Agent& agent);

}  // namespace nclink
