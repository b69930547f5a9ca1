#include "driver/driver_runner.hpp"
#include "gated_driver.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <condition_variable>
#include <future>
#include <map>
#include <mutex>
#include <thread>

using namespace nclink;
using driver_detail::DriverRunner;
using test::GatedDriver;

namespace {

class ThrowingDriver : public SimpleDriver {
public:
    Result<Json> read_one(const PointRef&) override { throw std::runtime_error("bus error"); }
    Result<void> write(const WriteRequest&) override { throw std::runtime_error("bus error"); }
};

std::vector<PointRef> points(std::initializer_list<const char*> ids) {
    std::vector<PointRef> out;
    for (const char* id : ids) out.push_back({id, DataKind::single});
    return out;
}

}  // namespace

TEST_CASE("a read that overruns its deadline answers Timeout (203) for each item") {
    auto driver = std::make_shared<GatedDriver>(false);
    DriverRunner::Options o;
    o.call_timeout = std::chrono::milliseconds(30);
    DriverRunner runner(driver, o, Logger());
    const auto results = runner.read(points({"a", "b"}));
    REQUIRE(results.size() == 2);
    for (const auto& r : results) {
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().code == ErrorCode::timeout);
    }
    CHECK(runner.timeouts() == 1);
    driver->release();
    // The driver is free again: the next read answers.
    const auto later = runner.read(points({"c"}), std::chrono::seconds(10));
    REQUIRE(later[0].ok());
    CHECK(later[0].value() == "c");
}

TEST_CASE("calls into a serialized driver never overlap, a concurrent driver's do") {
    for (bool concurrent : {false, true}) {
        auto driver = std::make_shared<GatedDriver>(concurrent);
        DriverRunner runner(driver, {}, Logger());
        std::vector<std::thread> callers;
        std::atomic<int> ok{0};
        for (int i = 0; i < 4; ++i)
            callers.emplace_back([&] {
                auto r = runner.read(points({"x"}), std::chrono::seconds(20));
                if (r[0].ok()) ++ok;
            });
        if (concurrent) {
            // Two workers: two calls get inside before the gate opens.
            while (driver->inside.load() < 2) std::this_thread::yield();
        } else {
            while (driver->inside.load() < 1) std::this_thread::yield();
            std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a second call would be inside by now
        }
        driver->release();
        for (auto& t : callers) t.join();
        CHECK(ok == 4);
        CHECK(driver->max_inside == (concurrent ? 2 : 1));
    }
}

TEST_CASE("a driver that throws answers Unavailable and the runner keeps serving") {
    DriverRunner runner(std::make_shared<ThrowingDriver>(), {}, Logger());
    auto r = runner.read(points({"a"}));
    REQUIRE_FALSE(r[0].ok());
    CHECK(r[0].error().code == ErrorCode::unavailable);
    CHECK_THAT(r[0].error().message, Catch::Contains("bus error"));
    WriteRequest w;
    w.id = "a";
    auto wr = runner.write(w);
    REQUIRE_FALSE(wr.ok());
    CHECK(wr.error().code == ErrorCode::unavailable);
    auto again = runner.read(points({"b"}));
    CHECK_FALSE(again[0].ok());
}

TEST_CASE("stop closes the driver, calls after stop are refused") {
    auto driver = std::make_shared<GatedDriver>(false);
    driver->release();
    DriverRunner runner(driver, {}, Logger());
    CHECK(runner.read(points({"a"}))[0].ok());
    runner.stop();
    CHECK(driver->closed);
    auto r = runner.read(points({"a"}));
    REQUIRE_FALSE(r[0].ok());
    CHECK(r[0].error().code == ErrorCode::unavailable);
}

TEST_CASE("a driver stuck at shutdown is abandoned, not waited for forever") {
    auto driver = std::make_shared<GatedDriver>(false);
    {
        DriverRunner::Options o;
        o.call_timeout = std::chrono::milliseconds(10);
        DriverRunner runner(driver, o, Logger());
        (void)runner.read(points({"a"}));  // times out; the worker stays inside the driver
        runner.stop(std::chrono::milliseconds(20));
        CHECK_FALSE(driver->closed);
    }
    driver->release();  // the abandoned worker finishes and exits on its own
    while (driver->reads.load() < 1) std::this_thread::yield();
}

TEST_CASE("a write past its deadline: withdrawn while queued, may still take effect once started") {
    auto driver = std::make_shared<GatedDriver>(false);
    DriverRunner::Options o;
    o.call_timeout = std::chrono::milliseconds(30);
    DriverRunner runner(driver, o, Logger());
    WriteRequest write;
    write.id = "b";
    SECTION("still queued: it never reaches the driver after the 203") {
        // A read holds the (serialized) driver: the write queues behind it.
        std::thread stuck([&] { runner.read(points({"a"}), std::chrono::seconds(30)); });
        while (driver->inside.load() == 0) std::this_thread::yield();
        const auto written = runner.write(write);
        REQUIRE_FALSE(written.ok());
        CHECK(written.error().code == ErrorCode::timeout);
        CHECK_THAT(written.error().message, Catch::Contains("not written"));
        driver->release();
        stuck.join();
        // The queue has drained past where the write was: it was not run.
        CHECK(runner.read(points({"c"}), std::chrono::seconds(10))[0].ok());
        CHECK(driver->writes.load() == 0);
    }
    SECTION("started by the driver, not finished: it says so, and it lands") {
        const auto written = runner.write(write);
        REQUIRE_FALSE(written.ok());
        CHECK(written.error().code == ErrorCode::timeout);
        CHECK_THAT(written.error().message, Catch::Contains("may still take effect"));
        driver->release();
        CHECK(runner.read(points({"c"}), std::chrono::seconds(10))[0].ok());
        CHECK(driver->writes.load() == 1);
    }
}

TEST_CASE("a write from a task on the driver's own worker calls the driver in place") {
    auto driver = std::make_shared<GatedDriver>(false);
    driver->release();
    DriverRunner::Options o;
    o.call_timeout = std::chrono::milliseconds(5000);
    DriverRunner runner(driver, o, Logger());
    for (const bool unlocked : {true, false}) {
        std::promise<Result<void>> got;
        WriteRequest write;
        write.id = "b";
        auto body = [&] { got.set_value(runner.write(write)); };
        REQUIRE((unlocked ? runner.post_unlocked(body) : runner.post([&](Driver&) { body(); })));
        auto future = got.get_future();
        // Queued behind itself, a serialized runner would answer only at the deadline.
        REQUIRE(future.wait_for(std::chrono::seconds(2)) == std::future_status::ready);
        CHECK(future.get().ok());
    }
    CHECK(driver->writes.load() == 2);
    CHECK(runner.timeouts() == 0);
}

TEST_CASE("a read from a task on the driver's own worker calls the driver in place") {
    // Without the in-place path a serialized runner would queue the read
    // behind the very task waiting for it, and answer 203 after the deadline.
    auto driver = std::make_shared<GatedDriver>(false);
    driver->release();
    DriverRunner::Options o;
    o.call_timeout = std::chrono::milliseconds(5000);
    DriverRunner runner(driver, o, Logger());
    std::promise<std::vector<Result<Json>>> got;
    REQUIRE(runner.post([&](Driver&) { got.set_value(runner.read(points({"a", "b"}))); }));
    auto future = got.get_future();
    REQUIRE(future.wait_for(std::chrono::seconds(2)) == std::future_status::ready);
    const auto results = future.get();
    REQUIRE(results.size() == 2);
    CHECK(results[1].value() == Json("b"));
    CHECK(runner.timeouts() == 0);
}

TEST_CASE("tasks queued behind a driver stuck at shutdown are dropped, not run later") {
    auto driver = std::make_shared<GatedDriver>(false);
    std::atomic<int> ran_after{0};
    {
        DriverRunner::Options o;
        o.call_timeout = std::chrono::milliseconds(10);
        DriverRunner runner(driver, o, Logger());
        (void)runner.read(points({"a"}));  // the worker stays inside the driver
        REQUIRE(runner.post([&](Driver&) { ++ran_after; }));
        runner.stop(std::chrono::milliseconds(20));
    }
    driver->release();
    while (driver->reads.load() < 1) std::this_thread::yield();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK(ran_after == 0);
}

namespace {
// GatedDriver's read() blocks; read_samples() answers at once.
class TypedGatedDriver : public GatedDriver {
public:
    TypedGatedDriver() : GatedDriver(false) {}
    bool read_samples(const std::vector<PointRef>& pts, SampleValue* out) override {
        for (std::size_t i = 0; i < pts.size(); ++i) out[i] = SampleValue::int64(static_cast<std::int64_t>(i) + 7);
        return true;
    }
};
}  // namespace

TEST_CASE("typed direct reads: done, unsupported, busy behind a running call, refused after stop") {
    auto typed = std::make_shared<TypedGatedDriver>();
    DriverRunner runner(typed, {}, Logger());
    SampleValue out[2] = {SampleValue::float64(1), SampleValue::float64(1)};
    CHECK(runner.read_samples_direct(points({"a", "b"}), out, std::chrono::milliseconds(100)) == DriverRunner::TypedRead::done);
    CHECK(out[0].as_int64() == 7);
    CHECK(out[1].as_int64() == 8);

    // A read() stuck on a worker holds the serialized driver: the typed read
    // gives up after its wait, leaves nulls and counts a timeout.
    std::thread stuck([&] { (void)runner.read(points({"x"}), std::chrono::seconds(20)); });
    while (typed->inside.load() < 1) std::this_thread::yield();
    CHECK(runner.read_samples_direct(points({"a", "b"}), out, std::chrono::milliseconds(20)) == DriverRunner::TypedRead::busy);
    CHECK(out[0].is_null());
    CHECK(out[1].is_null());
    CHECK(runner.timeouts() == 1);
    typed->release();
    stuck.join();

    runner.stop();
    out[0] = SampleValue::float64(1);
    CHECK(runner.read_samples_direct(points({"a"}), out, std::chrono::milliseconds(20)) == DriverRunner::TypedRead::done);
    CHECK(out[0].is_null());  // the driver is closed: nothing read

    auto plain = std::make_shared<GatedDriver>(false);
    plain->release();
    DriverRunner plain_runner(plain, {}, Logger());
    CHECK(plain_runner.read_samples_direct(points({"a"}), out, std::chrono::milliseconds(100)) ==
          DriverRunner::TypedRead::unsupported);
}

namespace {

// Answers each point with the handle it got; bind numbers points from 10 up
// (a second bind from 20), "gone" not served.
class HandleEcho final : public Driver {
public:
    Result<void> bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) override {
        ++binds;
        for (std::size_t i = 0; i < points.size(); ++i)
            handles[i] = points[i].id == "gone" ? not_served : static_cast<PointHandle>(binds * 10 + i);
        return ok_result();
    }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        calls += points.size();
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = Json(points[i].handle);
    }
    MachineLinkStatus link() const override {
        if (down) return {MachineLink::disconnected, "cable"};
        return {};
    }
    int binds = 0;
    std::size_t calls = 0;
    std::atomic<bool> down{false};
};

std::vector<BindPoint> bind_points(std::initializer_list<const char*> ids) {
    std::vector<BindPoint> out;
    for (const char* id : ids) {
        BindPoint p;
        p.id = id;
        out.push_back(p);
    }
    return out;
}

}  // namespace

TEST_CASE("points of an earlier bind are re-resolved by id, not served ones never reach the driver") {
    auto driver = std::make_shared<HandleEcho>();
    DriverRunner runner(driver, {}, Logger());
    auto first = runner.bind(bind_points({"a", "b", "gone"}));
    REQUIRE(first.ok());
    const auto& table = *first.value();
    std::vector<PointRef> refs{*table.find("a"), *table.find("b")};
    auto now = runner.read(refs, table.generation());
    CHECK(now[0].value() == 10);
    CHECK(now[1].value() == 11);
    // A new model: "b" gone from it, "a" renumbered.
    auto second = runner.bind(bind_points({"b2", "a"}));
    REQUIRE(second.ok());
    CHECK(second.value()->generation() > table.generation());
    auto stale = runner.read(refs, table.generation());
    CHECK(stale[0].value() == 21);  // the current handle of "a"
    REQUIRE_FALSE(stale[1].ok());
    CHECK(stale[1].error().code == ErrorCode::unavailable);
    const std::size_t calls = driver->calls;
    // A hand-made ref (no generation) is resolved by id too.
    auto gone = runner.read({PointRef{"gone", DataKind::single}});
    CHECK_FALSE(gone[0].ok());
    CHECK(driver->calls == calls);  // not called for it
    CHECK(runner.current_ref("a").handle == 21);
}

TEST_CASE("while the machine link is down the runner answers 202 with the reason, without a driver call") {
    auto driver = std::make_shared<HandleEcho>();
    DriverRunner runner(driver, {}, Logger());
    driver->down = true;
    auto read = runner.read(points({"a"}));
    REQUIRE_FALSE(read[0].ok());
    CHECK(read[0].error().code == ErrorCode::unavailable);
    CHECK(read[0].error().message == "machine disconnected: cable");
    WriteRequest w;
    w.id = "a";
    CHECK(runner.write(w).error().message == "machine disconnected: cable");
    CHECK(driver->calls == 0);
    CHECK(runner.link().state == MachineLink::disconnected);
    runner.stop(std::chrono::milliseconds(1000));
}

TEST_CASE("a post_unlocked task holds the driver only while it reads, so a direct (sampling) read gets in meanwhile") {
    auto driver = std::make_shared<GatedDriver>(false);
    driver->release();  // reads answer at once
    DriverRunner runner(driver, {}, Logger());
    for (const bool unlocked : {true, false}) {
        std::promise<void> go;
        std::shared_future<void> may_go = go.get_future().share();
        std::atomic<bool> started{false}, done{false};
        std::vector<Result<Json>> in_task;
        auto body = [&] {
            started = true;
            may_go.wait();  // the task's own work: parsing a request, encoding an answer
            in_task = runner.read(points({"a"}));
            done = true;
        };
        REQUIRE((unlocked ? runner.post_unlocked(body) : runner.post([&](Driver&) { body(); })));
        while (!started.load()) std::this_thread::yield();
        std::vector<Result<Json>> direct;
        runner.read_direct(points({"b"}), direct, std::chrono::milliseconds(20));
        REQUIRE(direct.size() == 1);
        if (unlocked) {
            CHECK(direct[0].ok());
        } else {
            // post(): the task holds the driver the whole time.
            REQUIRE_FALSE(direct[0].ok());
            CHECK(direct[0].error().code == ErrorCode::timeout);
        }
        go.set_value();
        while (!done.load()) std::this_thread::yield();
        REQUIRE(in_task.size() == 1);
        CHECK(in_task[0].ok());  // its own read went through, in place
    }
}

namespace {

// Notes the thread of every read, per point id.
class ThreadNotingDriver : public Driver {
public:
    DriverInfo info() const override { return {"noting", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        std::lock_guard<std::mutex> lock(mutex);
        for (std::size_t i = 0; i < points.size(); ++i) {
            by[points[i].id] = std::this_thread::get_id();
            results[i] = Json(points[i].id);
        }
    }
    std::thread::id reader_of(const std::string& id) {
        std::lock_guard<std::mutex> lock(mutex);
        return by[id];
    }
    std::mutex mutex;
    std::map<std::string, std::thread::id> by;
};

}  // namespace

TEST_CASE("while the sampling thread serves reads, a request's read runs there, all of its chunks, in order") {
    auto driver = std::make_shared<ThreadNotingDriver>();
    DriverRunner runner(driver, {}, Logger());
    runner.start_serving_reads(std::chrono::minutes(10));  // this thread plays the sampling thread
    std::vector<PointRef> many;
    for (int i = 0; i < 200; ++i) many.push_back({"p" + std::to_string(i), DataKind::single});  // several chunks
    std::promise<std::vector<Result<Json>>> got;
    std::promise<std::thread::id> worker;
    REQUIRE(runner.post_unlocked([&] {
        worker.set_value(std::this_thread::get_id());
        got.set_value(runner.read(many));
    }));
    auto answer = got.get_future();
    while (answer.wait_for(std::chrono::milliseconds(0)) != std::future_status::ready)
        runner.serve_reads(std::chrono::steady_clock::now() + std::chrono::milliseconds(5));
    const auto results = answer.get();
    REQUIRE(results.size() == many.size());
    for (std::size_t i = 0; i < many.size(); ++i) CHECK(results[i].value() == many[i].id);
    CHECK(driver->reader_of("p0") == std::this_thread::get_id());
    CHECK(driver->reader_of("p199") == std::this_thread::get_id());
    CHECK(runner.reads_served() >= 2);
    const auto worker_id = worker.get_future().get();

    // Serving stopped: the worker reads in place again.
    runner.stop_serving_reads();
    std::promise<void> done;
    REQUIRE(runner.post_unlocked([&] {
        (void)runner.read(points({"after"}));
        done.set_value();
    }));
    done.get_future().wait();
    CHECK(driver->reader_of("after") == worker_id);
}

TEST_CASE("a concurrent driver's reads are not handed over: they do not exclude the sampler's") {
    auto driver = std::make_shared<GatedDriver>(true, true);
    DriverRunner runner(driver, {}, Logger());
    runner.start_serving_reads(std::chrono::minutes(10));
    std::promise<std::vector<Result<Json>>> got;
    REQUIRE(runner.post_unlocked([&] { got.set_value(runner.read(points({"a"}))); }));
    auto answer = got.get_future();
    REQUIRE(answer.wait_for(std::chrono::seconds(60)) == std::future_status::ready);  // nobody served it
    CHECK(answer.get()[0].value() == "a");
    CHECK(runner.reads_served() == 0);
}

TEST_CASE("a sampling read that waits for the driver held by a request is counted as a sampling wait") {
    auto driver = std::make_shared<GatedDriver>(false);
    DriverRunner runner(driver, {}, Logger());
    std::vector<Result<Json>> direct;
    driver->release();
    runner.read_direct(points({"a"}), direct, std::chrono::milliseconds(20));
    CHECK(direct[0].ok());
    CHECK(runner.sampling_waits() == 0);  // a free driver: no wait

    auto held = std::make_shared<GatedDriver>(false);
    DriverRunner busy(held, {}, Logger());
    std::atomic<bool> inside{false};
    REQUIRE(busy.post([&](Driver& d) {
        inside = true;
        (void)d.write(WriteRequest{});  // blocks until released
    }));
    while (!inside.load()) std::this_thread::yield();
    busy.read_direct(points({"b"}), direct, std::chrono::milliseconds(20));
    REQUIRE_FALSE(direct[0].ok());
    CHECK(busy.sampling_waits() == 1);
    held->release();
}
