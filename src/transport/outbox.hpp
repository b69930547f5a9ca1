// Ordered, bounded buffer of outgoing messages with an in-flight window.
// Shared by every transport so offline buffering behaves the same on MQTT
// and on the loopback: messages are handed to the link in publish order (by
// the publishing thread itself when nothing is waiting, else by the sender),
// never more than max_in_flight unacknowledged at once (paho
// refuses bursts beyond its own buffer, error -12), keeps QoS>=1 messages until
// acknowledged, and puts unacknowledged ones back when the link drops.
//
// The sender is serial work (core/serial_work.hpp), not a thread of its
// own: in a gateway a pollable of the shared work threads, so 1,000
// machines' outboxes share a few threads; alone, a host of one thread
// ("nclink-outbox"). Either way one hand-over at a time, in publish order.
#pragma once

#include "core/serial_work.hpp"

#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace nclink::transport_detail {

class Outbox {
public:
    /// Hands one message to the link. `attempt` identifies this send; the link
    /// reports the outcome with delivered(attempt) / failed(attempt), from any
    /// thread, possibly before send() returns. Returns false when the link
    /// refused it outright (the message stays queued and is retried shortly).
    /// Called on the sender thread or a publishing thread, one call at a time,
    /// without the outbox's state lock held.
    /// The message is the outbox's own, shared: a link may keep a reference
    /// to the payload instead of copying it (a Sample DTU can be megabytes).
    using SendFn = std::function<bool(const std::shared_ptr<const Message>&, std::uint64_t attempt)>;

    /// `work`: the shared work threads the sender runs on (gateway mode), or
    /// null for a sender thread of its own. `link_copies`: the link copies
    /// what send() hands it before it returns and keeps no reference
    /// (libmosquitto, the loopback; not paho), so a delivered message's
    /// shared state can serve the next push().
    Outbox(OutboxLimits limits, SendFn send, Logger logger, core_detail::PollHost* work = nullptr, bool link_copies = false);
    ~Outbox();
    Outbox(const Outbox&) = delete;
    Outbox& operator=(const Outbox&) = delete;

    /// Thread-safe. Drops the oldest waiting messages when over budget.
    Result<void> push(Message message);

    void link_up();
    /// Lowers (or restores, up to the configured limit) how many messages may
    /// be unacknowledged at once: the broker's MQTT 5 Receive Maximum
    /// (3.3.4.9), which the client library enforces by holding messages back.
    void set_window(std::size_t max_in_flight);
    /// Unacknowledged messages go back to waiting, in their original order.
    void link_down();

    void delivered(std::uint64_t attempt);
    void failed(std::uint64_t attempt);

    bool wait_drained(std::chrono::milliseconds timeout);
    void stop();

    void fill_stats(TransportStats& stats) const;
    /// Messages handed to the link and not yet delivered().
    std::size_t in_flight() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return in_flight_;
    }
    /// How often the sender ran (tests: no futile wake-ups).
    std::uint64_t sender_wakeups() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return sender_wakeups_;
    }

private:
    struct Entry {
        // Shared, so a send hands the link a reference, not a copy of a
        // payload that may be megabytes (the entry may be erased meanwhile).
        std::shared_ptr<Message> message;
        std::uint64_t attempt = 0;  // 0 = waiting, else in flight under this attempt id
    };

    /// The sender: hands over what the window allows, a turn of at most
    /// kSendsPerTurn (then it yields the shared thread and comes back at
    /// once); returns when it must look again.
    core_detail::PollHost::Time send_waiting();
    std::size_t cost(const Message& m) const { return m.topic.size() + m.payload.size(); }
    void drop_oldest_waiting_locked();
    /// An entry's message once the outbox is done with it: emptied and kept
    /// for the next push() when the link copies, nobody else holds it and
    /// fewer than kSpares are kept.
    void recycle_locked(std::shared_ptr<Message> message);
    void put_back_locked(std::uint64_t attempt);
    bool can_send_locked() const;
    /// Hands the first waiting message to the link; caller holds send_mutex_.
    bool send_first_waiting();

    static constexpr std::chrono::milliseconds kRetryPause{100};
    static constexpr std::size_t kSendsPerTurn = 64;
    // Messages kept for reuse: a push() takes one instead of allocating its
    // shared state (one heap allocation a DTU fewer; a gateway publishes
    // thousands a second, docs/performance.md). A few cover a steady flow,
    // where each message is acknowledged before the next few are pushed.
    static constexpr std::size_t kSpares = 4;

    const OutboxLimits limits_;
    const SendFn send_;
    const bool link_copies_;
    const Logger logger_;

    std::mutex send_mutex_;  // serializes hand-overs to the link (sender or fast path)
    mutable std::mutex mutex_;
    std::condition_variable drained_;
    std::deque<Entry> entries_;
    std::vector<std::shared_ptr<Message>> spares_;  // at most kSpares, reserved
    std::size_t bytes_ = 0;
    std::size_t in_flight_ = 0;
    std::size_t window_;  // min(limits_.max_in_flight, the broker's Receive Maximum)
    std::uint64_t next_attempt_ = 1;
    bool link_up_ = false;
    std::chrono::steady_clock::time_point paused_until_{};
    bool stopping_ = false;
    std::uint64_t published_ = 0;
    std::uint64_t dropped_ = 0;
    std::uint64_t dropped_bytes_ = 0;
    std::uint64_t drop_burst_ = 0;  // drops since the last log line
    std::uint64_t sender_wakeups_ = 0;
    core_detail::SerialWork sender_;  // last: stopped before the rest goes
};

}  // namespace nclink::transport_detail
