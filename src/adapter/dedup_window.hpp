// Remembers recent request @ids so a request delivered twice (QoS 1 resends,
// clients that retry) is handled once. Keyed by topic kind + ex + @id text;
// entries expire after `window` and at most `capacity` are kept (oldest
// forgotten first). Thread-safe; time comes from the injected clock.
#pragma once

#include <nclink/clock.hpp>

#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_set>

namespace nclink::detail {

class DedupWindow {
public:
    DedupWindow(std::chrono::milliseconds window, std::size_t capacity, std::shared_ptr<const Clock> clock)
        : window_(window), capacity_(capacity == 0 ? 1 : capacity), clock_(std::move(clock)) {}

    /// True the first time `key` is seen within the window (handle it),
    /// false for a repeat (ignore it).
    bool first_sighting(const std::string& key) {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto now = clock_->now();
        while (!order_.empty() && (now - order_.front().seen >= window_ || order_.size() >= capacity_)) {
            keys_.erase(order_.front().key);
            order_.pop_front();
        }
        if (!keys_.insert(key).second) return false;
        order_.push_back({key, now});
        return true;
    }

private:
    struct Entry {
        std::string key;
        Clock::Steady seen;
    };
    const std::chrono::milliseconds window_;
    const std::size_t capacity_;
    const std::shared_ptr<const Clock> clock_;
    std::mutex mutex_;
    std::deque<Entry> order_;
    std::unordered_set<std::string> keys_;
};

}  // namespace nclink::detail
