// Which applications are still there (8.2.18.3): the adapter notes every DTU
// from an application (by its ex_cid) and asks, on its housekeeping tick, for
// those silent longer than the lease. A Notify/State offline ends one at once.
// Thread-safe; time comes from the injected clock.
#pragma once

#include <nclink/clock.hpp>

#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace nclink::adapter_detail {

class ApplicationTracker {
public:
    explicit ApplicationTracker(std::chrono::milliseconds lease) : lease_(lease) {}

    /// True when `ex` was not known (its first DTU, or the first since it
    /// was gone): the adapter then watches its Notify/State.
    bool seen(const std::string& ex, Clock::Steady now) {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto [it, added] = last_seen_.insert_or_assign(ex, now);
        (void)it;
        return added;
    }
    /// Forgets `ex`; true when it was known (so its resources may exist).
    bool gone(const std::string& ex) {
        std::lock_guard<std::mutex> lock(mutex_);
        return last_seen_.erase(ex) != 0;
    }
    /// Removes and returns the applications silent for longer than the lease
    /// (none when the lease is 0).
    std::vector<std::string> expire(Clock::Steady now) {
        std::vector<std::string> out;
        if (lease_.count() <= 0) return out;
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = last_seen_.begin(); it != last_seen_.end();) {
            if (now - it->second > lease_) {
                out.push_back(it->first);
                it = last_seen_.erase(it);
            } else {
                ++it;
            }
        }
        return out;
    }

private:
    const std::chrono::milliseconds lease_;
    std::mutex mutex_;
    std::map<std::string, Clock::Steady> last_seen_;
};

}  // namespace nclink::adapter_detail
