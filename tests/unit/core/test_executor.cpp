// The request pool (src/core/executor.hpp): resident workers, and workers
// beyond them that start when every live one is busy and end once idle.
#include "core/executor.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <future>
#include <vector>

using namespace nclink::core_detail;
using nclink::test::eventually;
using namespace std::chrono_literals;

namespace {

// Tasks that hold their worker until released.
struct Gate {
    std::promise<void> open;
    std::shared_future<void> opened = open.get_future().share();
    std::atomic<int> running{0}, done{0};
    std::function<void()> task() {
        return [this] {
            ++running;
            opened.wait();
            ++done;
        };
    }
};

}  // namespace

TEST_CASE("a fixed pool starts all its workers and keeps them") {
    Executor pool(3);
    CHECK(pool.live() == 3);
    std::atomic<int> ran{0};
    for (int i = 0; i < 10; ++i) REQUIRE(pool.post([&] { ++ran; }));
    REQUIRE(eventually([&] { return ran == 10; }));
    std::this_thread::sleep_for(20ms);
    CHECK(pool.live() == 3);
}

TEST_CASE("an elastic pool grows while its workers are busy, up to its size, and shrinks back when idle") {
    Executor pool(3, 1, 30ms);
    CHECK(pool.live() == 1);

    // Quick tasks one at a time, each posted once the worker waits again:
    // the resident worker is enough.
    std::atomic<int> quick{0};
    for (int i = 0; i < 5; ++i) {
        REQUIRE(eventually([&] { return pool.idle() == 1; }));
        REQUIRE(pool.post([&] { ++quick; }));
        REQUIRE(eventually([&] { return quick == i + 1; }));
    }
    CHECK(pool.live() == 1);

    Gate gate;
    REQUIRE(pool.post(gate.task()));
    REQUIRE(eventually([&] { return gate.running == 1; }));
    REQUIRE(pool.post(gate.task()));  // the only worker is busy: a second one
    REQUIRE(eventually([&] { return gate.running == 2; }));
    CHECK(pool.live() == 2);
    REQUIRE(pool.post(gate.task()));
    REQUIRE(pool.post(gate.task()));  // at the cap: this one waits in the queue
    REQUIRE(eventually([&] { return gate.running == 3; }));
    CHECK(pool.live() == 3);
    CHECK(pool.queued() == 1);
    gate.open.set_value();
    REQUIRE(eventually([&] { return gate.done == 4; }));

    // The extra workers end after 30 ms without work; the resident one stays.
    REQUIRE(eventually([&] { return pool.live() == 1; }));
    std::this_thread::sleep_for(60ms);
    CHECK(pool.live() == 1);

    // A second burst starts them again (the ended ones were joined).
    Gate again;
    REQUIRE(pool.post(again.task()));
    REQUIRE(pool.post(again.task()));
    REQUIRE(eventually([&] { return again.running == 2; }));
    CHECK(pool.live() == 2);
    again.open.set_value();
    REQUIRE(eventually([&] { return again.done == 2; }));
}

TEST_CASE("stop() runs what is queued and joins every worker, the extra ones included") {
    auto pool = std::make_unique<Executor>(2, 1, 10s);
    Gate gate;
    std::atomic<int> after{0};
    REQUIRE(pool->post(gate.task()));
    REQUIRE(pool->post(gate.task()));
    REQUIRE(eventually([&] { return gate.running == 2; }));
    for (int i = 0; i < 5; ++i) REQUIRE(pool->post([&] { ++after; }));
    std::thread opener([&] {
        std::this_thread::sleep_for(20ms);
        gate.open.set_value();
    });
    pool->stop();
    opener.join();
    CHECK(gate.done == 2);
    CHECK(after == 5);
    CHECK(pool->live() == 0);
    CHECK_FALSE(pool->post([] {}));
    pool.reset();
}
