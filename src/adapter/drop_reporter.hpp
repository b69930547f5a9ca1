// Overload is never silent (docs/delivery.md, "Counted drops"): every loss
// is counted by cause, and logged once per burst. The counters live where
// the losses happen (transport, rings, spool, events); this looks at their
// sums, the causes of the statistics' "drops" object (read straight from
// the counters, without building it), once a second on the housekeeping: the first growth of a cause starts a burst (a warning),
// a second with no growth ends it (the burst's total at info).
// Pure bookkeeping; not thread-safe (one caller).
#pragma once

#include "feature/feature.hpp"  // DropCounts

#include <nclink/json.hpp>
#include <nclink/log.hpp>

#include <cstdint>
#include <map>
#include <string>

namespace nclink::adapter_detail {

/// The adapter's own causes (adapter_stats.cpp): the outbox's and the request intake's.
void add_adapter_drops(feature_detail::DropCounts& out, std::uint64_t offline_buffer_full, std::uint64_t requests_shed);
/// The statistics' "drops" object: every cause by name (adapter_stats.cpp).
Json drops_by_cause(const feature_detail::DropCounts& features, std::uint64_t offline_buffer_full, std::uint64_t requests_shed);

class DropReporter {
public:
    explicit DropReporter(const Logger& logger) : logger_(logger) {}

    /// `drops`: cause -> count so far (counts only grow). Allocates only
    /// for a cause it has not seen before.
    void observe(const feature_detail::DropCounts& drops) {
        for (const auto& [cause, count] : drops.causes()) {
            auto found = causes_.find(cause);
            if (found == causes_.end()) found = causes_.emplace(cause, Cause{}).first;
            auto& s = found->second;
            if (count > s.last) {
                if (!s.in_burst) {
                    logger_.warn("dropping ({}): {} so far; counted in the statistics' drops.{} (docs/delivery.md)", cause, count,
                                 cause);
                    s.in_burst = true;
                    s.burst_start = s.last;
                }
            } else if (s.in_burst) {
                logger_.info("drops ({}) stopped: {} in this burst, {} in all", cause, count - s.burst_start, count);
                s.in_burst = false;
            }
            s.last = count;
        }
    }

private:
    struct Cause {
        std::uint64_t last = 0;
        std::uint64_t burst_start = 0;
        bool in_burst = false;
    };
    const Logger& logger_;
    std::map<std::string, Cause> causes_;
};

}  // namespace nclink::adapter_detail
