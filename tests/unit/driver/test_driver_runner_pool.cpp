// DriverRunner on a shared WorkerPool (gateway mode): the same guarantees as
// on its own worker (serialized calls, in-place reads from its own tasks,
// abandoning a stuck driver at stop) plus: one machine's stuck driver does
// not hold up another machine's calls.
#include "driver/driver_runner.hpp"
#include "gated_driver.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <condition_variable>
#include <future>
#include <mutex>
#include <thread>

using namespace nclink;
using core_detail::WorkerPool;
using driver_detail::DriverRunner;
using nclink::test::eventually;
using namespace std::chrono_literals;

namespace {

using Gate = test::GatedDriver;

std::vector<PointRef> points(std::initializer_list<const char*> ids) {
    std::vector<PointRef> out;
    for (const char* id : ids) out.push_back({id, DataKind::single});
    return out;
}

DriverRunner::Options on(WorkerPool& pool, std::chrono::milliseconds timeout = 10s) {
    DriverRunner::Options o;
    o.call_timeout = timeout;
    o.pool = &pool;
    return o;
}

}  // namespace

TEST_CASE("on a pool, calls into a serialized driver never overlap, a concurrent driver's do") {
    WorkerPool pool(4, 10000ms, "t-drivers");
    for (bool concurrent : {false, true}) {
        auto driver = std::make_shared<Gate>(concurrent);
        DriverRunner runner(driver, on(pool), Logger());
        std::vector<std::thread> callers;
        std::atomic<int> ok{0};
        for (int i = 0; i < 4; ++i)
            callers.emplace_back([&] {
                if (runner.read(points({"x"}))[0].ok()) ++ok;
            });
        if (concurrent) {
            REQUIRE(eventually([&] { return driver->inside.load() == 2; }));
        } else {
            REQUIRE(eventually([&] { return driver->inside.load() == 1; }));
            std::this_thread::sleep_for(20ms);  // the pool has 3 more threads: a second call would be inside by now
        }
        driver->release();
        for (auto& t : callers) t.join();
        CHECK(ok == 4);
        CHECK(driver->max_inside == (concurrent ? 2 : 1));
    }
}

TEST_CASE("on a pool, a read from the driver's own task is made in place") {
    WorkerPool pool(1, 10000ms, "t-drivers");
    auto driver = std::make_shared<Gate>(false, true);
    DriverRunner runner(driver, on(pool), Logger());
    std::promise<std::vector<Result<Json>>> got;
    REQUIRE(runner.post([&](Driver&) { got.set_value(runner.read(points({"a", "b"}))); }));
    auto future = got.get_future();
    REQUIRE(future.wait_for(5s) == std::future_status::ready);
    CHECK(future.get().at(1).value() == Json("b"));
    CHECK(runner.timeouts() == 0);
}

TEST_CASE("one machine's stuck driver does not hold up another machine's calls on the pool") {
    WorkerPool pool(1, 20ms, "t-drivers");
    auto stuck = std::make_shared<Gate>(false);
    auto fine = std::make_shared<Gate>(false, true);
    DriverRunner a(stuck, on(pool, 30ms), Logger());
    DriverRunner b(fine, on(pool), Logger());
    const auto timed_out = a.read(points({"a"}));  // 203; the pool's one thread stays inside
    CHECK(timed_out[0].error().code == ErrorCode::timeout);
    std::this_thread::sleep_for(30ms);
    const auto answered = b.read(points({"b"}));
    REQUIRE(answered[0].ok());
    CHECK(pool.replacements() == 1);
    stuck->release();
    a.stop();
    b.stop();
    CHECK(stuck->closed);
    CHECK(fine->closed);
}

TEST_CASE("a runner on a pool abandons a stuck driver at stop and drops what is queued behind it") {
    WorkerPool pool(2, 10000ms, "t-drivers");
    auto driver = std::make_shared<Gate>(false);
    std::atomic<int> ran_after{0};
    {
        DriverRunner runner(driver, on(pool, 10ms), Logger());
        (void)runner.read(points({"a"}));  // stays inside the driver
        REQUIRE(runner.post([&](Driver&) { ++ran_after; }));
        runner.stop(20ms);
        CHECK_FALSE(driver->closed);
    }
    driver->release();
    REQUIRE(eventually([&] { return driver->reads.load() == 1; }));
    std::this_thread::sleep_for(20ms);
    CHECK(ran_after == 0);
}

TEST_CASE("many runners share a small pool and every call is answered") {
    WorkerPool pool(2, 10000ms, "t-drivers");
    std::vector<std::shared_ptr<Gate>> drivers;
    std::vector<std::unique_ptr<DriverRunner>> runners;
    for (int i = 0; i < 50; ++i) {
        drivers.push_back(std::make_shared<Gate>(false, true));
        runners.push_back(std::make_unique<DriverRunner>(drivers.back(), on(pool), Logger()));
    }
    std::vector<std::thread> callers;
    std::atomic<int> ok{0};
    for (int t = 0; t < 4; ++t)
        callers.emplace_back([&, t] {
            for (int k = 0; k < 200; ++k) {
                auto& runner = *runners[static_cast<std::size_t>((t * 13 + k) % 50)];
                if (runner.read(points({"p"}))[0].ok()) ++ok;
            }
        });
    for (auto& c : callers) c.join();
    CHECK(ok == 800);
    CHECK(pool.threads() == 2);
    for (auto& r : runners) r->stop();
    for (auto& d : drivers) CHECK(d->closed);
}
