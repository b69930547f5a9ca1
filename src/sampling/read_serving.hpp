// When the sampling thread runs the requests' reads of a serialized driver
// itself, in the gap after each tick (driver/read_handoff.hpp): while a
// channel of at most kServeReadsUpTo found the driver held by a request
// worker (DriverRunner::sampling_waits()) within the last kServeReadsFor. A
// worker preempted while it holds the driver costs such a channel null rows.
// Only then, because a handed-over read waits for the sampling thread's next
// gap and costs a thread switch each way (about 75 us per Query on the
// reference VM, docs/performance.md). Slower channels wait out a preempted
// worker within their interval. Sampling thread only (its own sample loop;
// the gateway's shared timer threads do not serve reads).
#pragma once

#include "driver/driver_runner.hpp"

#include <nclink/clock.hpp>

#include <chrono>
#include <cstdint>

namespace nclink::sampling_detail {

inline constexpr std::int64_t kServeReadsUpTo = 4'000'000;  // ns
inline constexpr auto kServeReadsFor = std::chrono::seconds(2);

class ReadServing {
public:
    explicit ReadServing(driver_detail::DriverRunner* driver) : driver_(driver) {}
    ReadServing(const ReadServing&) = delete;
    ReadServing& operator=(const ReadServing&) = delete;
    ~ReadServing() {
        if (period_ > 0) driver_->stop_serving_reads();
    }

    /// After a tick: `fastest` is the shortest interval of the channels that
    /// read the driver (0: none), `until_next` the time to the next tick.
    /// Serves handed-over reads in the gap when serving is on.
    void between_ticks(std::int64_t fastest, Clock::Steady::duration until_next) {
        if (driver_ == nullptr) return;
        const bool fast = fastest > 0 && fastest <= kServeReadsUpTo;
        const auto waits = driver_->sampling_waits();
        const bool waited = waits != waits_seen_;
        waits_seen_ = waits;
        if (!fast && period_ == 0) return;  // no channel to protect: no clock read per tick
        const auto now = std::chrono::steady_clock::now();
        if (fast && waited) serve_until_ = now + kServeReadsFor;
        const std::int64_t wanted = fast && now < serve_until_ ? fastest : 0;
        if (wanted != period_) {
            if (period_ > 0) driver_->stop_serving_reads();
            // A read waits about one interval for the next gap; the
            // patience covers a sampler that was itself not scheduled.
            if (wanted > 0) driver_->start_serving_reads(std::chrono::nanoseconds(2 * wanted + 1'000'000));
            period_ = wanted;
        }
        if (period_ == 0) return;
        // A quarter of the interval stays free: the next tick's reads must
        // not wait for a chunk begun just before it, nor the sampling thread
        // run so long that it is scheduled late (a tenth left 0.7-2 % of the
        // rows late in the request flood).
        const auto budget = until_next - std::chrono::nanoseconds(period_ / 4);
        if (budget > Clock::Steady::duration::zero()) driver_->serve_reads(now + budget);
    }

private:
    driver_detail::DriverRunner* const driver_;
    std::int64_t period_ = 0;  // ns; 0: not serving
    std::uint64_t waits_seen_ = 0;
    std::chrono::steady_clock::time_point serve_until_{};
};

}  // namespace nclink::sampling_detail
