// A gateway's threads do not grow with its machines (docs/gateway.md
// "Threads: what is shared and what is not"): every machine's outbox sender,
// events engine, method status ticker and sample spool run as serial work on
// the shared work threads, beside the shared timer, request and driver
// threads and the one MQTT I/O thread. Before, each machine cost four threads
// of its own (a 200-machine gateway ran 800 more than a 0-machine one).
#include <nclink/client.hpp>
#include <nclink/gateway.hpp>

#include "support/adapter_fixture.hpp"  // FakeDriver, test_model_path
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

std::size_t threads_now() {
    std::size_t n = 0;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
        (void)task;
        ++n;
    }
    return n;
}

// The pools, set small and explicit so the bound below does not depend on
// the box's cores.
constexpr std::size_t kTimer = 2, kRequest = 2, kDriver = 2, kWork = 2;
// Besides the pools: the deadline watchdog, the MQTT I/O thread, and room
// for a driver thread started to replace one that seemed stuck (a slow,
// shared box) and for threads of libraries that come and go.
constexpr std::size_t kOthers = 6;

// Thread names and how many of each ("nclink-work-0 x1, ..."), for the
// message of a failure.
std::string thread_names() {
    std::map<std::string, int> names;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
        std::ifstream comm(task.path() / "comm");
        std::string name;
        std::getline(comm, name);
        ++names[name];
    }
    std::string out;
    for (const auto& [name, n] : names) out += fmt::format("{}{} x{}", out.empty() ? "" : ", ", name, n);
    return out;
}

struct Counted {
    std::size_t added = 0;  ///< threads while serving minus threads before the gateway
    bool all_answer = false;
    std::string names;  ///< the process's threads while serving
};

Counted serve(const MosquittoBroker& broker, int machines) {
    GatewayConfig config;
    config.timer_threads = kTimer;
    config.request_threads = kRequest;
    config.driver_threads = kDriver;
    config.work_threads = kWork;
    for (int i = 0; i < machines; ++i) {
        MachineConfig m;
        m.adapter.broker_url = broker.url();
        m.adapter.model_path = test_model_path();
        m.adapter.dev_uuid = fmt::format("gwt-{}-{:03d}", machines, i);
        m.adapter.register_timeout = 300ms;
        m.id = m.adapter.dev_uuid;
        config.machines.push_back(std::move(m));
    }
    const std::size_t before = threads_now();
    Gateway gateway(config, [](const MachineConfig&) -> Result<std::shared_ptr<Driver>> {
        return std::shared_ptr<Driver>(std::make_shared<FakeDriver>());
    });
    REQUIRE(gateway.start().ok());
    REQUIRE(gateway.machines().size() == static_cast<std::size_t>(machines));
    REQUIRE(eventually(
        [&] {
            for (const auto& m : gateway.machines())
                if (m.state != AdapterState::normal) return false;
            return true;
        },
        120s));

    // Every machine's outbox has published (registration, its state) and
    // its features run; a few answer a Query through them.
    Counted counted;
    auto client = started_client(broker.url(), fmt::format("gwt-app-{}", machines), 10s);
    counted.all_answer = true;
    for (int i : {0, machines / 2, machines - 1}) {
        auto values = client->query(fmt::format("gwt-{}-{:03d}", machines, i), {QueryItem{"pos", std::nullopt}});
        counted.all_answer = counted.all_answer && values.ok() && values->size() == 1 && (*values)[0].status.ok;
    }
    client->stop();
    // The fewest seen over a second: threads that only pass through (a
    // start's helpers leaving) are not the gateway's.
    std::size_t least = threads_now();
    for (int i = 0; i < 10; ++i) {
        std::this_thread::sleep_for(100ms);
        least = std::min(least, threads_now());
    }
    counted.added = least > before ? least - before : 0;
    counted.names = thread_names();
    gateway.stop();
    return counted;
}

}  // namespace

TEST_CASE("gateway: 200 machines run on as many threads as 20, a constant set by the pools") {
    MosquittoBroker broker;
    const Counted twenty = serve(broker, 20);
    const Counted two_hundred = serve(broker, 200);
    INFO("threads added: 20 machines " << twenty.added << ", 200 machines " << two_hundred.added);
    INFO("threads at 200 machines: " << two_hundred.names);
    CHECK(twenty.all_answer);
    CHECK(two_hundred.all_answer);
    const std::size_t bound = kTimer + kRequest + kDriver + kWork + kOthers;
    CHECK(two_hundred.added <= bound);
    CHECK(twenty.added <= bound);
    // Ten times the machines, not one thread more (but a replaced driver
    // thread).
    CHECK(two_hundred.added <= twenty.added + 1);
}
