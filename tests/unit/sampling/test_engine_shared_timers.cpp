// Gateway mode: sampling engines on shared timer threads (PollHost) instead
// of two threads each (include/nclink/shared_threads.hpp).
#include "engine_fixture.hpp"

#include "core/poll_host.hpp"
#include "core/shared_threads_impl.hpp"

#include <set>

#include <dirent.h>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

std::size_t threads_in_process() {
    std::size_t n = 0;
    if (DIR* dir = opendir("/proc/self/task")) {
        while (const dirent* e = readdir(dir))
            if (e->d_name[0] != '.') ++n;
        closedir(dir);
    }
    return n;
}

struct HostedEngine {
    HostedEngine(core_detail::PollHost& host, const std::string& guid) : dev(guid) {
        driver = std::make_shared<CountingDriver>();
        runner = std::make_unique<driver_detail::DriverRunner>(driver, driver_detail::DriverRunner::Options{}, Logger{});
        sampling_detail::EngineDeps deps;
        deps.driver = runner.get();
        deps.clock = std::make_shared<SystemClock>();
        deps.dev = guid;
        deps.sink = [this](Message m) {
            std::lock_guard<std::mutex> lock(mutex);
            sent.push_back(std::move(m));
        };
        deps.timers = &host;
        engine = std::make_unique<sampling_detail::SamplingEngine>(std::move(deps));
    }
    ~HostedEngine() {
        engine->stop();
        engine.reset();
        runner->stop();
    }
    /// Every value of the channel's first column, over the DTUs received so far.
    std::vector<std::int64_t> column(const std::string& channel) {
        std::lock_guard<std::mutex> lock(mutex);
        std::vector<std::int64_t> out;
        for (const auto& m : sent) {
            if (m.topic != topics::sample(dev, channel)) continue;
            const Json dtu = Json::parse(m.payload);  // kept: the loop below borrows from it
            for (const auto& v : dtu.at("data")[0].at("data")) out.push_back(v.is_null() ? -1 : v.get<std::int64_t>());
        }
        return out;
    }
    std::string dev;
    std::shared_ptr<CountingDriver> driver;
    std::unique_ptr<driver_detail::DriverRunner> runner;
    std::mutex mutex;
    std::vector<Message> sent;
    std::unique_ptr<sampling_detail::SamplingEngine> engine;
};

}  // namespace

TEST_CASE("engines on shared timer threads start no threads and sample and upload on the host's") {
    core_detail::PollHost host(2, "t-timers");
    std::vector<std::unique_ptr<HostedEngine>> engines;
    for (int i = 0; i < 20; ++i) engines.push_back(std::make_unique<HostedEngine>(host, "dev" + std::to_string(i)));
    const std::size_t before = threads_in_process();
    for (auto& e : engines) {
        auto spec = EngineFixture::spec("ch", {"a"}, 5, 20);
        spec.topic = topics::sample(e->dev, "ch");
        REQUIRE(e->engine->add_channel(spec).ok());
        e->engine->start();
    }
    // With own threads: 40 more. Not "equal": a thread the fixtures started
    // may end meanwhile (seen once under qemu-arm: 24 where 25 were counted).
    CHECK(threads_in_process() <= before);
    CHECK(host.size() == 40);  // a scheduler and an uploader per engine
    REQUIRE(eventually([&] {
        for (auto& e : engines)
            if (e->column("ch").size() < 10) return false;
        return true;
    }));
    // The reads ran on the host's threads, not on the engines' own.
    std::set<std::thread::id> reading;
    for (auto& e : engines) {
        std::lock_guard<std::mutex> lock(e->driver->mutex);
        reading.insert(e->driver->threads.begin(), e->driver->threads.end());
    }
    CHECK(reading.size() <= 2);
    for (auto& e : engines) e->engine->stop();
    CHECK(host.size() == 0);
    // stop() published what the rings held: every row read reached the sink,
    // in order, once (values count the reads).
    for (auto& e : engines) {
        const auto values = e->column("ch");
        const auto stats = e->engine->stats().at(0);
        CHECK(values.size() == stats.rows_published);
        std::int64_t last = 0;
        for (auto v : values) {
            if (v < 0) continue;  // a missed tick
            CHECK(v > last);
            last = v;
        }
    }
}

TEST_CASE("a channel added to a running hosted engine is sampled at once, a removed one sends its last rows") {
    core_detail::PollHost host(1, "t-timers");
    HostedEngine e(host, "dev1");
    e.engine->start();
    // Nothing to do yet: the scheduler asks for its next poll in a second at most.
    REQUIRE(e.engine->add_channel(EngineFixture::spec("late", {"b"}, 5, 1000)).ok());
    REQUIRE(eventually([&] { return e.engine->stats().at(0).rows_sampled >= 3; }));
    REQUIRE(e.engine->remove_channel("late"));
    // Its upload interval is a second: the removal wakes the uploader to send
    // what was sampled.
    REQUIRE(eventually([&] { return !e.column("late").empty(); }));
    REQUIRE(eventually([&] { return e.engine->stats().empty(); }));
}

TEST_CASE("shared threads give the adapters sampling phases spread evenly over the period") {
    SharedThreads threads(SharedThreadsOptions{1, 1, 1, 1000, false});
    auto& impl = threads.impl();
    // 0, 1/2, 1/4, 3/4, 1/8, 5/8, 3/8, 7/8: the first n adapters are as far
    // apart as n places allow, however many are started.
    const std::vector<double> first{0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
    for (double expected : first) CHECK(impl.next_sampling_phase() == expected);
    std::set<double> places(first.begin(), first.end());
    for (std::uint32_t i = first.size(); i < SharedThreads::Impl::kSamplingPhases; ++i) {
        const double phase = impl.next_sampling_phase();
        CHECK(phase >= 0);
        CHECK(phase < 1);
        places.insert(phase);
    }
    CHECK(places.size() == SharedThreads::Impl::kSamplingPhases);  // every place once
    CHECK(impl.next_sampling_phase() == 0);                        // then round again
}
