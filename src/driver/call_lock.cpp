// The driver's call lock (call_lock.hpp).
#include "driver/call_lock.hpp"

#include <cerrno>
#include <ctime>
#include <system_error>
#include <thread>

namespace nclink::driver_detail {

CallLock::CallLock() {
#if !defined(__SANITIZE_THREAD__)
    pthread_mutexattr_t attr;
    if (pthread_mutexattr_init(&attr) != 0) return;
    if (pthread_mutexattr_setprotocol(&attr, PTHREAD_PRIO_INHERIT) == 0 && pthread_mutex_init(&pi_mutex_, &attr) == 0)
        pi_ready_ = true;
    pthread_mutexattr_destroy(&attr);
#endif
}

CallLock::~CallLock() {
    if (pi_ready_) pthread_mutex_destroy(&pi_mutex_);
}

void CallLock::serialize() {
    if (!pi_ready_) return;
    // Probe the timed wait once, from another thread while this one holds
    // the mutex (only a contended wait reaches the kernel), with a deadline
    // already past: a platform whose PI futexes lack it (an emulator, an old
    // kernel) keeps the reader-writer lock instead of failing every
    // sampler's wait. Once per driver, at start.
    if (pthread_mutex_lock(&pi_mutex_) != 0) return;
    int waited = 0;
    std::thread([&] { waited = pi_wait_until(std::chrono::steady_clock::now()); }).join();
    pthread_mutex_unlock(&pi_mutex_);
    pi_ = waited == ETIMEDOUT;
}

void CallLock::lock() {
    if (!pi_) return rw_.lock();
    if (const int e = pthread_mutex_lock(&pi_mutex_); e != 0)
        throw std::system_error(e, std::generic_category(), "driver call lock");
}

void CallLock::unlock() {
    if (!pi_) return rw_.unlock();
    pthread_mutex_unlock(&pi_mutex_);
}

bool CallLock::try_lock() { return pi_ ? pthread_mutex_trylock(&pi_mutex_) == 0 : rw_.try_lock(); }

void CallLock::lock_shared() { pi_ ? lock() : rw_.lock_shared(); }

void CallLock::unlock_shared() { pi_ ? unlock() : rw_.unlock_shared(); }

bool CallLock::try_lock_shared() { return pi_ ? try_lock() : rw_.try_lock_shared(); }

bool CallLock::pi_lock_until(std::chrono::steady_clock::time_point deadline) { return pi_wait_until(deadline) == 0; }

int CallLock::pi_wait_until(std::chrono::steady_clock::time_point deadline) {
    // The steady clock is CLOCK_MONOTONIC (libstdc++): a clock step cannot
    // stretch the wait. PI futexes take it since Linux 5.14 (FUTEX_LOCK_PI2).
    const auto since_epoch = deadline.time_since_epoch();
    const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch);
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(seconds.count());
    ts.tv_nsec = static_cast<long>(std::chrono::duration_cast<std::chrono::nanoseconds>(since_epoch - seconds).count());
    int e = pthread_mutex_clocklock(&pi_mutex_, CLOCK_MONOTONIC, &ts);
    if (e == EINVAL) {  // an older kernel: the same wait on the wall clock
        const auto left = deadline - std::chrono::steady_clock::now();
        timespec now{};
        clock_gettime(CLOCK_REALTIME, &now);
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
        long long total = static_cast<long long>(now.tv_nsec) + (ns > 0 ? ns : 0);
        ts.tv_sec = now.tv_sec + static_cast<time_t>(total / 1000000000LL);
        ts.tv_nsec = static_cast<long>(total % 1000000000LL);
        e = pthread_mutex_timedlock(&pi_mutex_, &ts);
    }
    return e;
}

}  // namespace nclink::driver_detail
