#include "driver/read_handoff.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>
#include <vector>

using namespace nclink;
using driver_detail::ReadHandoff;
using namespace std::chrono_literals;

namespace {

// A job of `steps` steps that notes which thread ran each one.
struct SteppedJob {
    explicit SteppedJob(int steps, std::chrono::milliseconds each = 0ms) : total(steps), pause(each) {}
    bool step() {
        std::this_thread::sleep_for(pause);
        by.push_back(std::this_thread::get_id());
        return static_cast<int>(by.size()) >= total;
    }
    const int total;
    const std::chrono::milliseconds pause;
    std::vector<std::thread::id> by;
};

// Serves until `served` steps ran in all (test's serving thread).
void serve_until(ReadHandoff& handoff, std::uint64_t served) {
    while (handoff.steps_served() < served) handoff.serve(std::chrono::steady_clock::now() + 1s);
}

}  // namespace

TEST_CASE("with nothing serving, a job is not taken and runs no step") {
    ReadHandoff handoff;
    SteppedJob job(1);
    const ReadHandoff::Step step = [&] { return job.step(); };
    CHECK_FALSE(handoff.run(step));
    CHECK(job.by.empty());
    CHECK_FALSE(handoff.serving());
}

TEST_CASE("the serving thread runs every step of a handed job, and run() returns once it is complete") {
    ReadHandoff handoff;
    handoff.open(10min);  // never withdrawn here
    SteppedJob job(3);
    const ReadHandoff::Step step = [&] { return job.step(); };
    auto worker = std::async(std::launch::async, [&] { return handoff.run(step); });
    serve_until(handoff, 3);
    CHECK(worker.get());
    REQUIRE(job.by.size() == 3);
    for (const auto& id : job.by) CHECK(id == std::this_thread::get_id());
    CHECK_FALSE(handoff.has_work());
}

TEST_CASE("a job left unfinished at the end of a gap goes back, and its worker finishes it after the patience") {
    ReadHandoff handoff;
    handoff.open(50ms);
    SteppedJob job(4, 2ms);
    const ReadHandoff::Step step = [&] { return job.step(); };
    std::promise<std::thread::id> worker_id;
    auto worker = std::async(std::launch::async, [&] {
        worker_id.set_value(std::this_thread::get_id());
        if (handoff.run(step)) return true;
        while (!step()) {
        }
        return false;
    });
    const auto worker_thread = worker_id.get_future().get();
    while (!handoff.has_work()) std::this_thread::yield();
    // A gap shorter than one step: one step runs, the job goes back.
    CHECK(handoff.serve(std::chrono::steady_clock::now() + 1ms) == 1);
    CHECK_FALSE(worker.get());  // withdrawn after the patience, finished by its worker
    REQUIRE(job.by.size() == 4);
    CHECK(job.by[0] == std::this_thread::get_id());
    for (std::size_t i = 1; i < job.by.size(); ++i) CHECK(job.by[i] == worker_thread);
    CHECK_FALSE(handoff.has_work());
    CHECK(handoff.serve(std::chrono::steady_clock::now() + 1s) == 0);  // nothing runs twice
}

TEST_CASE("a gap that has already ended runs no step") {
    ReadHandoff handoff;
    handoff.open(20ms);
    SteppedJob job(1);
    const ReadHandoff::Step step = [&] { return job.step(); };
    auto worker = std::async(std::launch::async, [&] { return handoff.run(step); });
    while (!handoff.has_work()) std::this_thread::yield();
    CHECK(handoff.serve(std::chrono::steady_clock::now() - 1ms) == 0);
    CHECK_FALSE(worker.get());
    CHECK(job.by.empty());
}

TEST_CASE("close() hands the queued jobs back to their workers without waiting out the patience") {
    ReadHandoff handoff;
    handoff.open(10min);
    SteppedJob job(1);
    const ReadHandoff::Step step = [&] { return job.step(); };
    auto worker = std::async(std::launch::async, [&] { return handoff.run(step); });
    while (!handoff.has_work()) std::this_thread::yield();
    handoff.close();
    REQUIRE(worker.wait_for(60s) == std::future_status::ready);  // not 10 minutes
    CHECK_FALSE(worker.get());
    CHECK(job.by.empty());
    CHECK_FALSE(handoff.has_work());
}

TEST_CASE("the serving thread waiting for work wakes when a job is handed over, and not when serving ends") {
    ReadHandoff handoff;
    handoff.open(10min);
    auto waiter = std::async(std::launch::async, [&] { return handoff.wait_for_work(std::chrono::steady_clock::now() + 10min); });
    SteppedJob job(1);
    const ReadHandoff::Step step = [&] { return job.step(); };
    auto worker = std::async(std::launch::async, [&] { return handoff.run(step); });
    REQUIRE(waiter.wait_for(60s) == std::future_status::ready);
    CHECK(waiter.get());
    serve_until(handoff, 1);
    CHECK(worker.get());

    auto idle = std::async(std::launch::async, [&] { return handoff.wait_for_work(std::chrono::steady_clock::now() + 10min); });
    handoff.close();
    REQUIRE(idle.wait_for(60s) == std::future_status::ready);
    CHECK_FALSE(idle.get());
    CHECK_FALSE(handoff.wait_for_work(std::chrono::steady_clock::now() + 1ms));
}
