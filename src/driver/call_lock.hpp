// The lock that keeps calls into one driver apart (DriverRunner): exclusive
// per call for a serialized driver, shared for the reads of a concurrent one.
//
// A serialized driver gets a priority-inheritance mutex
// (PTHREAD_PRIO_INHERIT). The sampling thread may run at SCHED_FIFO
// (sampling.rt_priority) and then waits for this lock at most one sample
// interval; the thread it waits for is a request worker at normal priority,
// which on a busy machine (a request flood: the flooding client, the broker
// and the adapter's MQTT threads on the same cores) is preempted while it
// holds the lock. Without inheritance the sampler waits out its interval
// behind threads of lower priority than its own and records a null row;
// with it, the holder runs at the waiter's priority until it lets go.
// Under normal scheduling inheritance changes nothing.
//
// A concurrent driver keeps a reader-writer lock (there is no
// priority-inheriting one), as do ThreadSanitizer builds (TSan does not
// model PI futexes).
// Thread-safe; choose the mode with serialize() before the first use.
#pragma once

#include <pthread.h>

#include <chrono>
#include <shared_mutex>

namespace nclink::driver_detail {

class CallLock {
public:
    CallLock();
    ~CallLock();
    CallLock(const CallLock&) = delete;
    CallLock& operator=(const CallLock&) = delete;

    /// Every call exclusive, through the priority-inheriting mutex (where
    /// the platform gives one). Before the first use.
    void serialize();
    /// True when calls go through the priority-inheriting mutex.
    bool inherits_priority() const noexcept { return pi_; }

    // Lockable, TimedLockable (exclusive)
    void lock();
    void unlock();
    bool try_lock();
    template <class Rep, class Period>
    bool try_lock_for(const std::chrono::duration<Rep, Period>& wait) {
        if (!pi_) return rw_.try_lock_for(wait);
        return pi_lock_until(std::chrono::steady_clock::now() +
                             std::chrono::duration_cast<std::chrono::steady_clock::duration>(wait));
    }
    template <class Clock, class Duration>
    bool try_lock_until(const std::chrono::time_point<Clock, Duration>& when) {
        if (!pi_) return rw_.try_lock_until(when);
        return pi_lock_until(std::chrono::steady_clock::now() +
                             std::chrono::duration_cast<std::chrono::steady_clock::duration>(when - Clock::now()));
    }

    // SharedTimedLockable (a concurrent driver's reads; exclusive when serialized)
    void lock_shared();
    void unlock_shared();
    bool try_lock_shared();
    template <class Rep, class Period>
    bool try_lock_shared_for(const std::chrono::duration<Rep, Period>& wait) {
        return pi_ ? try_lock_for(wait) : rw_.try_lock_shared_for(wait);
    }
    template <class Clock, class Duration>
    bool try_lock_shared_until(const std::chrono::time_point<Clock, Duration>& when) {
        return pi_ ? try_lock_until(when) : rw_.try_lock_shared_until(when);
    }

private:
    bool pi_lock_until(std::chrono::steady_clock::time_point deadline);
    int pi_wait_until(std::chrono::steady_clock::time_point deadline);  ///< 0, ETIMEDOUT or why not

    std::shared_timed_mutex rw_;
    pthread_mutex_t pi_mutex_;
    bool pi_ready_ = false;  // pi_mutex_ initialized with PTHREAD_PRIO_INHERIT
    bool pi_ = false;        // serialize() chose it
};

}  // namespace nclink::driver_detail
