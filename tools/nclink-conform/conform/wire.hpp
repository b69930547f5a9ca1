// The tester's raw link: publishes DTUs it builds itself and records every
// message that arrives (with the tester's arrival time), so each check sees
// exactly what the adapter sent. No client library in between: a DTU the
// client would drop as malformed is evidence here.
//
// Threads: the transport's callback thread appends to the log; the runner
// (one thread) publishes and waits. Every member is thread-safe.
#pragma once

#include <nclink/json.hpp>
#include <nclink/result.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace nclink::conform {

struct Captured {
    std::uint64_t seq = 0;  ///< arrival order, from 0
    Message message;
    std::int64_t wall_ms = 0;                  ///< tester's wall clock at arrival
    std::chrono::steady_clock::time_point at;  ///< tester's monotonic clock at arrival
};

using MessagePredicate = std::function<bool(const Captured&)>;

class Wire {
public:
    /// Takes over the transport's handlers (the transport must not be started).
    Wire(Transport& transport, std::string ex_cid);
    ~Wire();
    Wire(const Wire&) = delete;
    Wire& operator=(const Wire&) = delete;

    /// Subscribes `filters`, starts the transport, waits for the link and then
    /// for a message of its own to come back through the broker (so every
    /// subscription is in force). Fails with timeout (203) or the transport's error.
    Result<void> connect(const std::vector<std::string>& filters, std::chrono::milliseconds timeout);
    /// Stops the transport (the owner may also do it).
    void close();

    Result<void> publish(const std::string& topic, const Json& payload, int qos = 1);

    /// Sequence number the next arriving message will get.
    std::uint64_t mark() const;
    /// The first message with seq >= from matching `pred`, waiting up to `timeout`.
    std::optional<Captured> wait_for(std::uint64_t from, const MessagePredicate& pred, std::chrono::milliseconds timeout);
    /// Waits until `count` messages with seq >= from match `pred` (or the timeout) and returns those seen.
    std::vector<Captured> wait_count(std::uint64_t from, const MessagePredicate& pred, std::size_t count,
                                     std::chrono::milliseconds timeout);
    /// Every message so far with seq >= from matching `pred`.
    std::vector<Captured> collect(std::uint64_t from, const MessagePredicate& pred) const;

    /// A fresh "@id" for a request: "<ex>-<n>".
    std::string next_msg_id();
    const std::string& ex_cid() const noexcept { return ex_; }
    bool connected() const;

private:
    void on_message(const Message& message);

    Transport& transport_;
    std::string ex_;
    mutable std::mutex mutex_;
    std::condition_variable arrived_;
    std::deque<Captured> log_;
    std::uint64_t next_seq_ = 0;
    std::uint64_t dropped_ = 0;  // oldest entries dropped past the cap
    LinkState link_ = LinkState::disconnected;
    std::uint64_t ids_ = 0;
    bool closed_ = false;
};

}  // namespace nclink::conform
