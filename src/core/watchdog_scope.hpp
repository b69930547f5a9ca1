// One owner's arms on a DeadlineWatchdog that several owners share (gateway
// mode). close() makes every callback armed through the scope a no-op from
// then on, and waits for one that is running, so the owner can go away while
// its deadlines are still in the watchdog's heap.
#pragma once

#include "core/deadline_watchdog.hpp"

#include <functional>
#include <memory>
#include <mutex>

namespace nclink::core_detail {

class WatchdogScope {
public:
    explicit WatchdogScope(DeadlineWatchdog& watchdog) : watchdog_(watchdog) {}
    ~WatchdogScope() { close(); }
    WatchdogScope(const WatchdogScope&) = delete;
    WatchdogScope& operator=(const WatchdogScope&) = delete;

    /// As DeadlineWatchdog::arm(); false after close().
    bool arm(DeadlineWatchdog::Time at, std::function<void()> on_expiry) {
        {
            std::lock_guard<std::mutex> lock(state_->mutex);
            if (!state_->open) return false;
        }
        return watchdog_.arm(at, [state = state_, run = std::move(on_expiry)] {
            std::lock_guard<std::mutex> lock(state->mutex);
            if (state->open) run();
        });
    }
    /// Idempotent. Not from an armed callback.
    void close() {
        std::lock_guard<std::mutex> lock(state_->mutex);
        state_->open = false;
    }

private:
    struct State {
        std::mutex mutex;  // held while a callback runs
        bool open = true;
    };
    DeadlineWatchdog& watchdog_;
    std::shared_ptr<State> state_ = std::make_shared<State>();
};

}  // namespace nclink::core_detail
