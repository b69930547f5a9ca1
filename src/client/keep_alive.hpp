// Application liveness (GB/T 41970-2022 3.22/3.23): an adapter judges an
// application offline when no DTU came from it within an interval, and then
// releases what it registered (events, dynamic sample channels). Receiving
// DTUs says nothing to the adapter, so the client sends one itself: for every
// adapter at which it holds a registration, a Query of one registered item
// every `interval` (a legal, idempotent request the adapter answers anyway;
// the agent counts it as a sign of life too). docs/delivery.md, "Liveness".
//
// Pure bookkeeping: the caller passes the time. Thread-safe (hold() runs on
// the dispatch thread, release() on any caller's thread).
#pragma once

#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace nclink::client_detail {

class KeepAlive {
public:
    using Clock = std::chrono::steady_clock;

    /// interval 0 = never (the registrations then live as long as the
    /// adapter's application lease after the application's last request).
    explicit KeepAlive(std::chrono::milliseconds interval) : interval_(interval) {}

    /// A registration `key` ("event:<id>", "sample:<channel>") at `dev`,
    /// kept alive by querying `item`. The first at a device schedules it.
    void hold(const std::string& dev, const std::string& key, const std::string& item, Clock::time_point now) {
        if (interval_.count() <= 0 || item.empty()) return;
        std::lock_guard<std::mutex> lock(mutex_);
        auto& device = devices_[dev];
        if (device.items.empty()) device.next = now + interval_;
        device.items[key] = item;
    }
    void release(const std::string& dev, const std::string& key) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = devices_.find(dev);
        if (it == devices_.end()) return;
        it->second.items.erase(key);
        if (it->second.items.empty()) devices_.erase(it);
    }
    /// The devices due at `now`, each with the item to query; rescheduled.
    std::vector<std::pair<std::string, std::string>> due(Clock::time_point now) {
        std::vector<std::pair<std::string, std::string>> out;
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& [dev, device] : devices_) {
            if (device.next > now) continue;
            out.emplace_back(dev, device.items.begin()->second);
            device.next = now + interval_;
        }
        return out;
    }
    /// Every device due at once (after a reconnect: the outage may have
    /// eaten most of the lease).
    void all_due(Clock::time_point now) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& entry : devices_) entry.second.next = now;
    }
    std::optional<Clock::time_point> next_due() const {
        std::lock_guard<std::mutex> lock(mutex_);
        std::optional<Clock::time_point> next;
        for (const auto& entry : devices_)
            if (!next || entry.second.next < *next) next = entry.second.next;
        return next;
    }
    std::size_t devices() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return devices_.size();
    }

private:
    struct Device {
        std::map<std::string, std::string> items;  // registration key -> item to query
        Clock::time_point next;
    };
    const std::chrono::milliseconds interval_;
    mutable std::mutex mutex_;
    std::map<std::string, Device> devices_;
};

}  // namespace nclink::client_detail
