// Remembers recent request @ids so a request delivered twice (QoS 1 resends,
// clients that retry) is handled once. Keyed by topic kind + ex + @id text;
// entries expire after `window` and at most `capacity` are kept (oldest
// forgotten first). Thread-safe; time comes from the injected clock.
#pragma once

#include <nclink/clock.hpp>
#include <nclink/json.hpp>

#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_set>

namespace nclink::adapter_detail {

class DedupWindow {
public:
    DedupWindow(std::chrono::milliseconds window, std::size_t capacity, std::shared_ptr<const Clock> clock)
        : window_(window), capacity_(capacity == 0 ? 1 : capacity), clock_(std::move(clock)) {}

    /// The key of a request: its kind, its application's ex (behind its
    /// length: an ex may hold any byte but '/') and its @id as JSON would
    /// write it, except that a string @id goes unescaped behind one quote
    /// (distinct strings stay distinct, and no number, bool or null starts
    /// with a quote). Built on the receive thread for every request, hence
    /// no formatting and no dump() of the usual string @id.
    static std::string key(std::string_view kind, std::string_view ex, const Json& msg_id) {
        std::string out;
        const std::string* text = msg_id.is_string() ? &msg_id.get_ref<const std::string&>() : nullptr;
        out.reserve(kind.size() + ex.size() + 8 + (text ? text->size() : 24));
        out.append(kind).append(1, '|').append(std::to_string(ex.size())).append(1, ':').append(ex).append(1, '|');
        if (text) out.append(1, '"').append(*text);
        else out.append(msg_id.dump());
        return out;
    }

    /// True the first time `key` is seen within the window (handle it),
    /// false for a repeat (ignore it).
    bool first_sighting(std::string key) {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto now = clock_->now();
        while (!order_.empty() && (now - order_.front().seen >= window_ || order_.size() >= capacity_)) {
            keys_.erase(keys_.find(*order_.front().key));
            order_.pop_front();
        }
        const auto [kept, added] = keys_.insert(std::move(key));
        if (!added) return false;
        order_.push_back({&*kept, now});  // elements of an unordered_set never move
        return true;
    }

private:
    struct Entry {
        const std::string* key;
        Clock::Steady seen;
    };
    const std::chrono::milliseconds window_;
    const std::size_t capacity_;
    const std::shared_ptr<const Clock> clock_;
    std::mutex mutex_;
    std::deque<Entry> order_;
    std::unordered_set<std::string> keys_;
};

}  // namespace nclink::adapter_detail
