#include "sampling/sleeper.hpp"

#include <cerrno>
#include <ctime>

namespace nclink::sampling_detail {

void NanosleepSleeper::sleep_until(Clock::Steady deadline, std::uint64_t /*seen: wake() is not delivered*/) {
    // steady_clock is CLOCK_MONOTONIC in libstdc++ on Linux, so its epoch
    // matches: the deadline goes to the kernel as an absolute time.
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline.time_since_epoch()).count();
    if (ns <= 0) return;
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

void PollingSleeper::sleep_until(Clock::Steady deadline, std::uint64_t seen) {
    const auto real_limit = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
    std::unique_lock<std::mutex> lock(mutex_);
    while (wakes_ == seen && clock_->now() < deadline && std::chrono::steady_clock::now() < real_limit) cv_.wait_for(lock, step_);
}

void PollingSleeper::wake() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ++wakes_;
    }
    cv_.notify_all();
}

std::uint64_t PollingSleeper::wakes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return wakes_;
}

void ManualSleeper::sleep_until(Clock::Steady deadline, std::uint64_t seen) {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto entry = sleepers_.insert(sleepers_.end(), {deadline, seen});
    cv_.notify_all();
    cv_.wait(lock, [&] { return wakes_ != seen || clock_->now() >= deadline; });
    sleepers_.erase(entry);
    cv_.notify_all();
}

void ManualSleeper::wake() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ++wakes_;
    }
    cv_.notify_all();
}

void ManualSleeper::advance(std::chrono::nanoseconds by) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        clock_->advance(by);
    }
    cv_.notify_all();
}

std::uint64_t ManualSleeper::wakes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return wakes_;
}

bool ManualSleeper::idle_locked(int threads) const {
    if (static_cast<int>(sleepers_.size()) != threads) return false;
    const auto now = clock_->now();
    for (const auto& [deadline, wakes] : sleepers_)
        if (deadline <= now || wakes != wakes_) return false;  // about to run
    return true;
}

bool ManualSleeper::wait_idle(int threads, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, [&] { return idle_locked(threads); });
}

}  // namespace nclink::sampling_detail
