// How the sampling and uploader threads wait for their next absolute
// deadline. Production: clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME)
// (steady_clock is CLOCK_MONOTONIC on Linux). Tests: a sleeper that waits for
// a ManualClock to reach the deadline, so timing logic runs on fake time.
#pragma once

#include <nclink/clock.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <list>
#include <utility>

namespace nclink::sampling_detail {

class Sleeper {
public:
    virtual ~Sleeper() = default;
    /// Waits until `deadline` (on the engine's Clock), or until wake() has
    /// been called since wakes() returned `seen` (take `seen` BEFORE doing the
    /// work that decided the deadline, so a wake() meanwhile is not lost).
    /// May return early (spuriously): callers re-check their clock.
    virtual void sleep_until(Clock::Steady deadline, std::uint64_t seen) = 0;
    /// Makes sleep_until() return soon (stop, channel set changed). Thread-safe.
    virtual void wake() = 0;
    /// How many times wake() was called. Thread-safe.
    virtual std::uint64_t wakes() const { return 0; }
    /// Longest single wait the loops ask for, so a wake() that a sleeper
    /// cannot deliver (clock_nanosleep) is noticed within it.
    virtual std::chrono::nanoseconds max_wait() const { return std::chrono::milliseconds(20); }
};

/// clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME): the deadline is absolute,
/// so error never accumulates. wake() is not instant: the loops wait at most
/// max_wait() (20 ms) at a time. Only for a SystemClock engine.
class NanosleepSleeper final : public Sleeper {
public:
    void sleep_until(Clock::Steady deadline, std::uint64_t seen) override;
    void wake() override {}
};

/// Waits on a condition variable in steps of `step` real time, re-reading
/// `clock` (any Clock: for adapter tests on a ManualClock), and returns after
/// at most 20 ms of real time whatever the clock says. Not precise.
class PollingSleeper final : public Sleeper {
public:
    PollingSleeper(std::shared_ptr<const Clock> clock, std::chrono::microseconds step = std::chrono::microseconds(1000))
        : clock_(std::move(clock)), step_(step) {}
    void sleep_until(Clock::Steady deadline, std::uint64_t seen) override;
    void wake() override;
    std::uint64_t wakes() const override;

private:
    std::shared_ptr<const Clock> clock_;
    const std::chrono::microseconds step_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::uint64_t wakes_ = 0;
};

/// For unit tests: sleep_until() blocks until the ManualClock is advanced
/// (through advance()) to the deadline, or wake(). Counts waits so a test
/// can wait until the threads are idle.
class ManualSleeper final : public Sleeper {
public:
    explicit ManualSleeper(std::shared_ptr<ManualClock> clock) : clock_(std::move(clock)) {}
    void sleep_until(Clock::Steady deadline, std::uint64_t seen) override;
    void wake() override;
    std::uint64_t wakes() const override;
    std::chrono::nanoseconds max_wait() const override { return std::chrono::hours(1); }
    /// Advances the clock and wakes sleepers whose deadline passed.
    void advance(std::chrono::nanoseconds by);
    /// Waits (real time, up to `timeout`) until `threads` threads are blocked
    /// in sleep_until() with deadlines still in the future: they have done
    /// everything due at the current fake time. False on timeout.
    bool wait_idle(int threads, std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));

private:
    bool idle_locked(int threads) const;

    std::shared_ptr<ManualClock> clock_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::list<std::pair<Clock::Steady, std::uint64_t>> sleepers_;  // deadline and wake count of the threads blocked now
    std::uint64_t wakes_ = 0;
};

}  // namespace nclink::sampling_detail
