// The sampling thread runs the requests' reads of a serialized driver while a
// fast channel finds the driver held by request workers (sampling_engine.cpp,
// read_handoff.hpp).
#include "engine_fixture.hpp"

#include <pthread.h>

#include <future>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

// Notes the name of the thread of each read, per point id.
class ThreadNamingDriver : public Driver {
public:
    DriverInfo info() const override { return {"naming", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        char name[32] = {};
        pthread_getname_np(pthread_self(), name, sizeof(name));
        std::lock_guard<std::mutex> lock(mutex);
        for (std::size_t i = 0; i < points.size(); ++i) {
            by[points[i].id] = name;
            results[i] = Json(1);
        }
    }
    std::string reader_of(const std::string& id) {
        std::lock_guard<std::mutex> lock(mutex);
        return by[id];
    }
    std::mutex mutex;
    std::map<std::string, std::string> by;
};

// A request's read (a post_unlocked() task, as the adapter's Query path
// makes), while fake time moves on so the sampling thread ticks; returns the
// name of the thread that read `id`.
std::string request_read(EngineFixture& f, ThreadNamingDriver& driver, const std::string& id) {
    std::promise<void> done;
    auto finished = done.get_future();
    REQUIRE(f.runner->post_unlocked([&] {
        (void)f.runner->read({PointRef{id, DataKind::single}});
        done.set_value();
    }));
    while (finished.wait_for(200us) != std::future_status::ready) f.sleeper->advance(1ms);
    return driver.reader_of(id);
}

// A request worker holds the driver until the sampling thread has waited
// for it in vain at least once.
void hold_driver_through_a_tick(EngineFixture& f) {
    std::promise<void> release;
    auto released = release.get_future().share();
    std::atomic<bool> inside{false};
    REQUIRE(f.runner->post([&, released](Driver&) {
        inside = true;
        released.wait();
    }));
    while (!inside.load()) std::this_thread::yield();
    const auto before = f.runner->sampling_waits();
    while (f.runner->sampling_waits() == before) {
        f.sleeper->advance(1ms);
        std::this_thread::sleep_for(1ms);
    }
    release.set_value();
}

}  // namespace

TEST_CASE("after a 1 ms channel found the driver held by a request, the requests' reads run on the sampling thread") {
    auto driver = std::make_shared<ThreadNamingDriver>();
    EngineFixture f({}, true, driver);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("fast", {"a"}, 1, 10)).ok());
    f.engine->start();
    REQUIRE(f.sleeper->wait_idle(2));

    // No contention yet: a request reads on its own worker.
    CHECK(request_read(f, *driver, "before") == "nclink-driver");
    CHECK(f.runner->reads_served() == 0);

    hold_driver_through_a_tick(f);
    // A read handed over between two gaps of the sampling thread is taken
    // back by its worker after the patience: on a loaded machine one attempt
    // may miss, so several are made.
    int on_sampler = 0;
    for (int i = 0; i < 50 && on_sampler == 0; ++i)
        if (request_read(f, *driver, "q" + std::to_string(i)) == "nclink-sampler") ++on_sampler;
    CHECK(on_sampler == 1);
    CHECK(f.runner->reads_served() >= 1);
    f.engine->stop();
}

TEST_CASE("a channel slower than 4 ms leaves the requests' reads on their workers, even after it waited for the driver") {
    auto driver = std::make_shared<ThreadNamingDriver>();
    EngineFixture f({}, true, driver);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("slow", {"a"}, 5, 50)).ok());
    f.engine->start();
    REQUIRE(f.sleeper->wait_idle(2));
    hold_driver_through_a_tick(f);
    for (int i = 0; i < 10; ++i) CHECK(request_read(f, *driver, "q" + std::to_string(i)) == "nclink-driver");
    CHECK(f.runner->reads_served() == 0);
    f.engine->stop();
}
