// The sample stream, offered to whoever watches values (events): the
// sampling service hands each row it drains to the tap, on its uploader
// thread, and observers that watch one of the row's items are called there.
// Observers must be quick (no driver calls, no blocking I/O).
//
// The tap also knows which items are sampled at all, so a watcher can choose
// between the stream and polling the driver.
#pragma once

#include <nclink/sample_value.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace nclink::feature_detail {

class SampleTap {
public:
    /// `values[i]` belongs to `ids[i]`; text values are borrowed for the call.
    using Observer = std::function<void(const std::vector<std::string>& ids, const SampleValue* values, std::int64_t time_ms)>;

    /// Thread-safe. Returns a handle for remove().
    std::uint64_t add(Observer observer) {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto id = ++next_;
        observers_[id] = std::make_shared<Observer>(std::move(observer));
        active_ = true;
        return id;
    }
    void remove(std::uint64_t handle) {
        std::lock_guard<std::mutex> lock(mutex_);
        observers_.erase(handle);
        active_ = !observers_.empty();
    }
    /// Cheap check for the uploader: skip building rows nobody watches.
    bool active() const noexcept { return active_.load(std::memory_order_relaxed); }

    /// Called by the sampling service (uploader thread) per drained row.
    void deliver(const std::vector<std::string>& ids, const SampleValue* values, std::int64_t time_ms) const {
        std::vector<std::shared_ptr<Observer>> snapshot;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            for (const auto& entry : observers_) snapshot.push_back(entry.second);
        }
        for (const auto& observer : snapshot) (*observer)(ids, values, time_ms);
    }

    /// The sampling service says which items its running channels read.
    void set_sampled(const std::set<std::string>& ids) {
        std::vector<std::string> sorted(ids.begin(), ids.end());
        std::lock_guard<std::mutex> lock(mutex_);
        sampled_.swap(sorted);
    }
    bool sampled(const std::string& id) const {
        std::lock_guard<std::mutex> lock(mutex_);
        return std::binary_search(sampled_.begin(), sampled_.end(), id);
    }

private:
    mutable std::mutex mutex_;
    std::map<std::uint64_t, std::shared_ptr<Observer>> observers_;
    // Sorted; a vector, not a set: a tree node per sampled item was about
    // 50 bytes more an item in every machine of a gateway.
    std::vector<std::string> sampled_;
    std::uint64_t next_ = 0;
    std::atomic<bool> active_{false};
};

}  // namespace nclink::feature_detail
