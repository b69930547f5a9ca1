// Traffic of a terminal, for monitoring (docs/metrics.md): DTUs in and out by
// topic kind, and how long requests took to answer. Snapshots: plain values,
// taken under no lock the caller has to know about.
#pragma once

#include <nclink/export.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace nclink {

/// A histogram as Prometheus keeps one: per bucket the observations at or
/// below its upper bound and above the previous one (not cumulative here; the
/// renderer accumulates), the last bucket everything above the last bound.
struct NCLINK_API HistogramSnapshot {
    std::vector<double> upper_bounds;   ///< seconds, ascending (the +Inf bucket is implied)
    std::vector<std::uint64_t> counts;  ///< upper_bounds.size() + 1 entries
    std::uint64_t count = 0;            ///< every observation
    double sum = 0;                     ///< seconds, over every observation
};

/// Counters only grow.
struct NCLINK_API TrafficStats {
    /// DTUs received, by topic kind (the names of to_string(TopicKind):
    /// "query_request", "sample", ...; "unparsed" for topics that are no
    /// NC-Link topic).
    std::map<std::string, std::uint64_t> dtus_in;
    /// DTUs handed to the transport, by topic kind.
    std::map<std::string, std::uint64_t> dtus_out;
    /// Requests by kind: from receipt to the answer (for Method/Call: to its
    /// acceptance). Only kinds with at least one observation are listed.
    std::map<std::string, HistogramSnapshot> request_seconds;
};

}  // namespace nclink
