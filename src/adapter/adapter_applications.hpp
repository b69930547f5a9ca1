// Application liveness (8.2.18.3, 3.22), one object: which applications
// still talk to this adapter, and what happens when one is gone. Every DTU
// from an application is noted (its Notify/State is subscribed at its first
// one); a Notify/State offline, or silence for the lease, ends it: counted,
// logged, and `gone` called so the features release what it registered.
//
// Threads: seen() and on_notify_state() on the transport's callback thread
// (never block there); expire() on the housekeeping thread; released() any.
// The tracker (application_tracker.hpp) holds the only lock.
#pragma once

#include "adapter/application_tracker.hpp"

#include <nclink/clock.hpp>
#include <nclink/log.hpp>
#include <nclink/topics.hpp>
#include <nclink/transport.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace nclink::adapter_detail {

class ApplicationWatch {
public:
    /// `gone(ex)`: application `ex` is offline for this adapter (the
    /// features' on_application_gone). `transport` and `logger` outlive it.
    ApplicationWatch(Transport& transport, std::string dev, std::chrono::milliseconds lease, const Logger& logger,
                     std::function<void(const std::string&)> gone);

    /// A DTU from application `ex` reached the adapter at `now`.
    void seen(const std::string& ex, Clock::Steady now);
    /// A Notify/State that is not retained (a retained one comes from
    /// subscribing, not from a change).
    void on_notify_state(const ParsedTopic& topic, const std::string& payload);
    /// Ends the applications silent for longer than the lease.
    void expire(Clock::Steady now);
    /// Applications judged offline so far (AdapterStats::applications_released).
    std::uint64_t released() const { return released_.load(); }

private:
    void gone(const std::string& ex, std::string_view why);

    Transport& transport_;
    const std::string dev_;
    const std::chrono::milliseconds lease_;
    const Logger& logger_;
    const std::function<void(const std::string&)> on_gone_;
    ApplicationTracker tracker_;
    std::atomic<std::uint64_t> released_{0};
};

}  // namespace nclink::adapter_detail
