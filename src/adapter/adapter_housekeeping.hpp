// The adapter's housekeeping, one object: a periodic pass that registers
// again when no agent answered (AdapterLink::tick_registration), ends silent
// applications (ApplicationWatch::expire), tries kept responses again while
// connected (AdapterLink::retry_kept) and, once a second, logs every loss
// once per burst (drop_reporter.hpp).
//
// Threads: a pollable of a host: the shared timer threads of a gateway, or
// a single adapter's background threads; without one (tests), a thread of
// its own "nclink-house" (start() to stop()). wake() from any
// thread. The registration and lease clocks are the injected clock, polled
// every kHousekeepingPeriod, so tests drive them with a ManualClock.
#pragma once

#include "adapter/adapter_applications.hpp"
#include "adapter/adapter_link.hpp"
#include "adapter/drop_reporter.hpp"
#include "core/poll_host.hpp"

#include <nclink/clock.hpp>
#include <nclink/json.hpp>
#include <nclink/log.hpp>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

namespace nclink::adapter_detail {

/// How often housekeeping looks at registration retries, leases and drops
/// (real time; the registration and lease clocks are the injected clock).
inline constexpr std::chrono::milliseconds kHousekeepingPeriod{50};
/// The same on shared timer threads (gateway mode, real clock only): a
/// thousand machines at 50 ms would be 20,000 passes a second for retries
/// measured in seconds and leases in minutes.
inline constexpr std::chrono::milliseconds kSharedHousekeepingPeriod{250};

class Housekeeping {
public:
    /// `drops`: adds the statistics' "drops" causes now to its argument
    /// (false while there is nothing to look at). `timers`: the host it runs on every `period`,
    /// or null for a thread of its own (every kHousekeepingPeriod).
    /// Everything referenced outlives it.
    using DropsNow = std::function<bool(feature_detail::DropCounts&)>;
    Housekeeping(AdapterLink& link, ApplicationWatch& applications, DropsNow drops, std::shared_ptr<const Clock> clock,
                 const Logger& logger, core_detail::PollHost* timers, std::chrono::milliseconds period = kSharedHousekeepingPeriod);
    ~Housekeeping() { stop(); }

    void start();
    /// Returns when no pass runs any more. Idempotent.
    void stop();
    /// Runs a pass soon (a registration went out or was answered).
    void wake();

private:
    void run();   // the own thread's loop
    void pass();  // one pass (also the pollable on shared threads)

    AdapterLink& link_;
    ApplicationWatch& applications_;
    const DropsNow drops_;
    const std::shared_ptr<const Clock> clock_;
    core_detail::PollHost* const timers_;
    const std::chrono::milliseconds period_;                   // on a host
    DropReporter drop_reporter_;                               // passes only (one at a time)
    feature_detail::DropCounts drop_counts_;                   // passes only: filled again each second
    std::chrono::steady_clock::time_point last_drop_check_{};  // passes only

    std::mutex mutex_;  // stopping_, with wake_
    std::condition_variable wake_;
    bool stopping_ = false;
    std::thread thread_;                   // without shared timers
    core_detail::PollHost::Handle entry_;  // with shared timers
};

}  // namespace nclink::adapter_detail
