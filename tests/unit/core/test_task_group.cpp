#include "core/task_group.hpp"
#include "core/watchdog_scope.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <future>
#include <thread>

using namespace nclink::core_detail;
using nclink::test::eventually;
using namespace std::chrono_literals;

TEST_CASE("a task group's close() waits for its own tasks, not for another group's") {
    auto executor = std::make_shared<Executor>(2);
    TaskGroup mine(executor), other(executor);
    std::promise<void> release_other;
    std::shared_future<void> other_may_go = release_other.get_future().share();
    std::atomic<bool> other_running{false};
    REQUIRE(other.post([&] {
        other_running = true;
        other_may_go.wait();
    }));
    REQUIRE(eventually([&] { return other_running.load(); }));
    std::atomic<int> done{0};
    for (int i = 0; i < 20; ++i)
        REQUIRE(mine.post([&] {
            std::this_thread::sleep_for(1ms);
            ++done;
        }));
    mine.close();  // returns although `other` still holds a worker
    CHECK(done == 20);
    CHECK(mine.outstanding() == 0);
    CHECK_FALSE(mine.post([] {}));
    CHECK(other.outstanding() == 1);
    release_other.set_value();
    other.close();
    CHECK(other.outstanding() == 0);
}

TEST_CASE("a task that throws still counts as done") {
    auto executor = std::make_shared<Executor>(1);
    TaskGroup group(executor);
    REQUIRE(group.post([] { throw 42; }));
    group.close();
    CHECK(group.outstanding() == 0);
}

TEST_CASE("a closed watchdog scope runs none of its callbacks, close() waits for a running one") {
    DeadlineWatchdog watchdog;
    SECTION("closed before the deadline") {
        std::atomic<int> ran{0};
        WatchdogScope scope(watchdog);
        REQUIRE(scope.arm(std::chrono::steady_clock::now() + 20ms, [&] { ++ran; }));
        scope.close();
        CHECK_FALSE(scope.arm(std::chrono::steady_clock::now(), [&] { ++ran; }));
        std::this_thread::sleep_for(50ms);
        CHECK(ran == 0);
    }
    SECTION("closed while one runs") {
        std::atomic<bool> started{false}, finished{false};
        WatchdogScope scope(watchdog);
        REQUIRE(scope.arm(std::chrono::steady_clock::now(), [&] {
            started = true;
            std::this_thread::sleep_for(50ms);
            finished = true;
        }));
        REQUIRE(eventually([&] { return started.load(); }));
        scope.close();
        CHECK(finished);
    }
    SECTION("another scope on the same watchdog keeps running") {
        std::atomic<int> ran{0};
        WatchdogScope closed(watchdog), open(watchdog);
        REQUIRE(closed.arm(std::chrono::steady_clock::now() + 10ms, [&] { ran += 100; }));
        REQUIRE(open.arm(std::chrono::steady_clock::now() + 10ms, [&] { ++ran; }));
        closed.close();
        REQUIRE(eventually([&] { return ran == 1; }));
        std::this_thread::sleep_for(20ms);
        CHECK(ran == 1);
    }
}
