#include "core/periodic_thread.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

using namespace nclink::core_detail;
using nclink::test::eventually;
using namespace std::chrono_literals;

TEST_CASE("a periodic thread runs its task at once and again after each period") {
    PeriodicThread thread;
    std::atomic<int> runs{0};
    REQUIRE(thread.start(
        1ms, [&] { ++runs; }, "test-periodic"));
    REQUIRE(thread.running());
    REQUIRE(eventually([&] { return runs.load() >= 3; }));
    thread.stop();
    REQUIRE_FALSE(thread.running());
    const int after_stop = runs.load();
    std::this_thread::sleep_for(5ms);
    REQUIRE(runs.load() == after_stop);  // joined: no run after stop() returned
}

TEST_CASE("stopping a periodic thread does not wait out its period") {
    PeriodicThread thread;
    std::promise<void> first_run;
    auto ran = first_run.get_future();
    std::atomic<bool> once{false};
    // A period far longer than any test: only the wake-up can end the wait.
    REQUIRE(thread.start(
        std::chrono::hours(24),
        [&] {
            if (!once.exchange(true)) first_run.set_value();
        },
        "test-periodic"));
    REQUIRE(ran.wait_for(10s) == std::future_status::ready);
    auto stopped = std::async(std::launch::async, [&] { thread.stop(); });
    // Generous bound: a stop that waited for the period would take a day.
    REQUIRE(stopped.wait_for(60s) == std::future_status::ready);
    REQUIRE_FALSE(thread.running());
}

TEST_CASE("a periodic thread starts once, stop is idempotent, and it can start again") {
    PeriodicThread thread;
    std::atomic<int> a{0}, b{0};
    REQUIRE(thread.start(
        1ms, [&] { ++a; }, "test-periodic"));
    REQUIRE_FALSE(thread.start(
        1ms, [&] { ++b; }, "test-periodic"));  // already running: ignored
    REQUIRE(eventually([&] { return a.load() >= 1; }));
    thread.stop();
    thread.stop();
    REQUIRE(b.load() == 0);
    REQUIRE(thread.start(
        1ms, [&] { ++b; }, "test-periodic"));
    REQUIRE(eventually([&] { return b.load() >= 1; }));
}
