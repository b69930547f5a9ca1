// The driver's call lock (driver/call_lock.hpp): a serialized driver's calls
// go through a priority-inheriting mutex, so a SCHED_FIFO sampler waiting
// for the driver is not held up behind threads of lower priority than its
// own while a request worker at normal priority holds the driver.
#include "driver/call_lock.hpp"
#include "driver/driver_runner.hpp"
#include "gated_driver.hpp"

#include <catch2/catch.hpp>

#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

using namespace nclink;
using namespace std::chrono_literals;
using driver_detail::CallLock;
using driver_detail::DriverRunner;

namespace {

// Pins the calling thread to CPU 0 at SCHED_FIFO `priority`; false where
// the process may not (no CAP_SYS_NICE / RLIMIT_RTPRIO).
bool fifo_on_cpu0(int priority) {
    cpu_set_t cpus;
    CPU_ZERO(&cpus);
    CPU_SET(0, &cpus);
    if (pthread_setaffinity_np(pthread_self(), sizeof cpus, &cpus) != 0) return false;
    sched_param param{};
    param.sched_priority = priority;
    return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
}

bool fifo_allowed() {
    bool allowed = false;
    std::thread([&] { allowed = fifo_on_cpu0(1); }).join();
    return allowed;
}

}  // namespace

TEST_CASE("call lock: a serialized driver's lock is exclusive and timed, shared reads of a concurrent one are shared") {
    CallLock serialized;
    serialized.serialize();
#if !defined(__SANITIZE_THREAD__)
    CHECK(serialized.inherits_priority());
#endif
    std::unique_lock<CallLock> held(serialized);
    std::atomic<bool> got{true};
    std::thread([&] { got = serialized.try_lock_for(20ms); }).join();
    CHECK_FALSE(got);
    std::thread([&] { got = serialized.try_lock_shared_for(20ms); }).join();  // shared is exclusive when serialized
    CHECK_FALSE(got);
    held.unlock();
    std::thread([&] {
        got = serialized.try_lock_until(std::chrono::system_clock::now() + 1s);
        if (got) serialized.unlock();
    }).join();
    CHECK(got);

    CallLock concurrent;
    CHECK_FALSE(concurrent.inherits_priority());
    std::shared_lock<CallLock> reader(concurrent);
    std::thread([&] {
        got = concurrent.try_lock_shared_for(20ms);
        if (got) concurrent.unlock_shared();
    }).join();
    CHECK(got);
    std::thread([&] { got = concurrent.try_lock_for(20ms); }).join();
    CHECK_FALSE(got);
}

TEST_CASE("call lock: the driver runner inherits priority for a serialized driver only") {
#if defined(__SANITIZE_THREAD__)
    WARN("ThreadSanitizer build: the call lock is a reader-writer lock here");
    return;
#endif
    DriverRunner serialized(std::make_shared<test::GatedDriver>(false, true), {}, {});
    DriverRunner concurrent(std::make_shared<test::GatedDriver>(true, true), {}, {});
    CHECK(serialized.inherits_priority());
    CHECK_FALSE(concurrent.inherits_priority());
}

// Priority inversion, the textbook case, on one CPU: a low-priority thread
// holds the lock, a middle one spins, a high one waits for the lock. With
// inheritance the holder runs at the waiter's priority, finishes and lets
// go while the middle one still spins; without it the middle one keeps the
// holder off the CPU until it stops. Ordering only, no timing is asserted.
TEST_CASE("call lock: a waiter of higher priority gets the lock before a middle-priority spinner ends") {
#if defined(__SANITIZE_THREAD__)
    WARN("ThreadSanitizer build: the call lock is a reader-writer lock here");
    return;
#endif
    if (!fifo_allowed()) {
        WARN("SCHED_FIFO not permitted here: priority inheritance not exercised");
        return;
    }
    CallLock lock;
    lock.serialize();
    REQUIRE(lock.inherits_priority());
    std::atomic<bool> low_holds{false}, middle_spinning{false}, high_waiting{false}, high_got{false};
    std::atomic<bool> middle_ended_first{false}, ok_low{true}, ok_middle{true}, ok_high{true};
    std::thread low([&] {
        ok_low = fifo_on_cpu0(10);
        std::unique_lock<CallLock> held(lock);
        low_holds = true;
        // Work that needs the CPU: it ends only when this thread gets it.
        while (!high_waiting.load()) std::this_thread::yield();
        volatile std::uint64_t x = 0;
        for (std::uint64_t i = 0; i < 2'000'000; ++i) x = x + i;
    });
    while (!low_holds.load()) std::this_thread::yield();
    std::thread middle([&] {
        ok_middle = fifo_on_cpu0(20);
        middle_spinning = true;
        const auto until = std::chrono::steady_clock::now() + 3s;  // bounded: without inheritance it ends this
        while (!high_got.load() && std::chrono::steady_clock::now() < until) {
        }
        if (!high_got.load()) middle_ended_first = true;
    });
    std::thread high([&] {
        ok_high = fifo_on_cpu0(30);
        while (!middle_spinning.load()) std::this_thread::yield();
        high_waiting = true;
        if (lock.try_lock_for(10s)) {
            high_got = true;
            lock.unlock();
        }
    });
    high.join();
    middle.join();
    low.join();
    REQUIRE(ok_low);
    REQUIRE(ok_middle);
    REQUIRE(ok_high);
    CHECK(high_got);
    CHECK_FALSE(middle_ended_first);
}
