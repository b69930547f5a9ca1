#include "core/worker_pool.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <future>
#include <mutex>
#include <vector>

using namespace nclink::core_detail;
using nclink::test::eventually;
using namespace std::chrono_literals;

TEST_CASE("a worker pool runs every task, in FIFO order on one thread") {
    WorkerPool pool(1, 1000ms, "t-pool");
    std::mutex mutex;
    std::vector<int> order;
    for (int i = 0; i < 100; ++i)
        REQUIRE(pool.post([&, i] {
            std::lock_guard<std::mutex> lock(mutex);
            order.push_back(i);
        }));
    REQUIRE(eventually([&] {
        std::lock_guard<std::mutex> lock(mutex);
        return order.size() == 100;
    }));
    for (int i = 0; i < 100; ++i) CHECK(order[i] == i);
    pool.stop();
    CHECK_FALSE(pool.post([] {}));
}

TEST_CASE("a task stuck past stuck_after gets a replacement thread, so others still run") {
    WorkerPool pool(1, 20ms, "t-pool");
    std::promise<void> unstick;
    std::shared_future<void> stuck_may_go = unstick.get_future().share();
    std::atomic<bool> inside{false}, left{false};
    REQUIRE(pool.post([&] {
        inside = true;
        stuck_may_go.wait();
        left = true;
    }));
    REQUIRE(eventually([&] { return inside.load(); }));
    std::this_thread::sleep_for(40ms);  // now past stuck_after
    std::atomic<bool> ran{false};
    REQUIRE(pool.post([&] { ran = true; }));
    CHECK(eventually([&] { return ran.load(); }));  // with one fixed thread it would wait for the stuck task
    CHECK(pool.replacements() == 1);
    CHECK(pool.threads() == 2);
    unstick.set_value();
    REQUIRE(eventually([&] { return left.load(); }));  // the task is done with this test's locals
}

TEST_CASE("a busy task that is not stuck yet gets no replacement: tasks queue") {
    WorkerPool pool(1, 10000ms, "t-pool");
    std::promise<void> release;
    std::shared_future<void> may_go = release.get_future().share();
    std::atomic<bool> inside{false}, ran{false};
    REQUIRE(pool.post([&] {
        inside = true;
        may_go.wait();
    }));
    REQUIRE(eventually([&] { return inside.load(); }));
    REQUIRE(pool.post([&] { ran = true; }));
    std::this_thread::sleep_for(30ms);
    CHECK_FALSE(ran);
    CHECK(pool.replacements() == 0);
    release.set_value();
    CHECK(eventually([&] { return ran.load(); }));
}

TEST_CASE("stop() runs what is queued and leaves a worker stuck past the grace behind") {
    auto release = std::make_shared<std::promise<void>>();
    std::shared_future<void> may_go = release->get_future().share();
    std::atomic<int> ran{0};
    {
        WorkerPool pool(2, 1000ms, "t-pool");
        REQUIRE(pool.post([may_go] { may_go.wait(); }));
        for (int i = 0; i < 10; ++i) REQUIRE(pool.post([&] { ++ran; }));
        pool.stop(50ms);  // returns although one worker is still inside its task
        CHECK(ran == 10);
    }
    release->set_value();  // the detached worker comes back to a pool that is gone, safely
    std::this_thread::sleep_for(20ms);
}
