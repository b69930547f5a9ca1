// What a source thread tells the driver: the machine link as link() answers
// it, and counters for tests and diagnostics. Thread-safe: the source thread
// writes, any SDK thread reads (one short lock).
#pragma once

#include <nclink/driver.hpp>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace nclink::mtconnect {

struct SourceCounters {
    std::uint64_t probes = 0;        ///< probes read (agent) / loaded (SHDR)
    std::uint64_t currents = 0;      ///< /current documents applied
    std::uint64_t samples = 0;       ///< /sample documents applied
    std::uint64_t observations = 0;  ///< observations (or SHDR values) applied
    std::uint64_t restarts = 0;      ///< agent instanceId changes seen
    std::uint64_t out_of_range = 0;  ///< /sample answered OUT_OF_RANGE (from fell out of the buffer)
    std::uint64_t failures = 0;      ///< requests or connections that failed
    std::uint64_t connects = 0;      ///< SHDR connections made
    std::uint64_t pongs = 0;         ///< SHDR "* PONG" answers received
};

class SourceStatus {
public:
    void connected() {
        std::lock_guard lock(mutex_);
        link_ = {MachineLink::connected, {}};
    }
    void disconnected(std::string reason) {
        std::lock_guard lock(mutex_);
        link_ = {MachineLink::disconnected, std::move(reason)};
    }
    MachineLinkStatus link() const {
        std::lock_guard lock(mutex_);
        return link_;
    }
    template <class F>
    void count(F&& f) {
        std::lock_guard lock(mutex_);
        f(counters_);
    }
    SourceCounters counters() const {
        std::lock_guard lock(mutex_);
        return counters_;
    }

private:
    mutable std::mutex mutex_;
    MachineLinkStatus link_{MachineLink::unknown, {}};
    SourceCounters counters_;
};

}  // namespace nclink::mtconnect
