// Values on their way to the events thread: rows of the sample stream (from
// the sampling uploader), driver pushes (Adapter::notify_value, any thread)
// and registrations to start (request workers). Producers never block on the
// evaluation; only values of watched items are kept, at most `capacity` of
// them (beyond it new values are dropped and counted: a stalled events thread
// must not grow memory without bound). Starting a registration is never dropped.
// Thread-safe.
#pragma once

#include <nclink/json.hpp>
#include <nclink/sample_value.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace nclink::events_detail {

/// A sample value as JSON: text as a string, serialized JSON parsed.
/// std::nullopt for a missed read (a null slot of the row), NaN/infinity and
/// JSON text that does not parse: no value was read, so there is nothing to
/// compare (a miss between two equal values is no change).
std::optional<Json> sample_value_to_json(const SampleValue& value);

class ValueInbox {
public:
    struct Item {
        std::string id;             ///< item id, or event id for an activation
        std::optional<Json> value;  ///< whole value (absent: activation without a known value)
        std::int64_t time_ms = 0;
        bool activation = false;
        std::chrono::steady_clock::time_point at{};  ///< activation: when the registration was made
        /// activation: ready once the registration's response is published
        /// (its events must not overtake it, 8.2.27.4).
        std::shared_future<void> responded;
    };
    struct Work {
        std::vector<Item> items;
        bool closed = false;
    };

    explicit ValueInbox(std::size_t capacity = 65536) : capacity_(capacity) {}

    void set_watched(std::set<std::string> items);
    void push_value(const std::string& id, const Json& value, std::int64_t time_ms);
    void push_row(const std::vector<std::string>& ids, const SampleValue* values, std::int64_t time_ms);
    /// Queued before the response goes out, so a value pushed by anyone who
    /// has seen the response is evaluated after the activation; `responded`
    /// becomes ready when the response is published.
    void push_activation(const std::string& event_id, std::optional<Json> whole, std::int64_t time_ms,
                         std::chrono::steady_clock::time_point at, std::shared_future<void> responded);

    /// Everything queued; waits for something (or close) when empty, at most
    /// `timeout` when given. Called by the one consumer.
    Work wait(std::optional<std::chrono::milliseconds> timeout);
    /// Everything queued, without waiting. Called by the one consumer.
    Work take();
    /// Called after every push, under the inbox's lock (so once close()
    /// returned it is never called again and may dangle): a consumer run as
    /// serial work (core/serial_work.hpp) is woken instead of sleeping in
    /// wait(). It must not call back into the inbox. Pushes before it is set
    /// wake nobody: the consumer looks once after setting it.
    void set_waker(std::function<void()> waker) {
        std::lock_guard<std::mutex> lock(mutex_);
        waker_ = std::move(waker);
    }
    /// Wakes the consumer for good; later pushes are ignored.
    void close();

    std::uint64_t dropped() const;

private:
    bool accept_locked();
    std::function<void()> waker_;  // mutex_

    const std::size_t capacity_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::set<std::string> watched_;
    std::deque<Item> items_;
    std::size_t values_ = 0;  // queued non-activation items
    std::uint64_t dropped_ = 0;
    bool closed_ = false;
};

}  // namespace nclink::events_detail
