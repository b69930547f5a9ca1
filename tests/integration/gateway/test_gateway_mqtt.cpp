// Gateway mode against a real mosquitto: many machines in one process, each
// its own terminal (own GUID, own connection, own state), one removed and
// added back at run time while the others keep serving.
#include <nclink/client.hpp>
#include <nclink/gateway.hpp>

#include "support/inbox.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"
#include "support/adapter_fixture.hpp"  // FakeDriver, test_model_path

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

MachineConfig machine(const MosquittoBroker& broker, int i) {
    MachineConfig m;
    m.adapter.broker_url = broker.url();
    m.adapter.model_path = test_model_path();
    m.adapter.dev_uuid = fmt::format("gw-{:02d}", i);
    m.adapter.register_timeout = 300ms;
    m.id = m.adapter.dev_uuid;
    return m;
}

MachineDriverFactory fake_drivers() {
    return [](const MachineConfig&) -> Result<std::shared_ptr<Driver>> {
        return std::shared_ptr<Driver>(std::make_shared<FakeDriver>());
    };
}

bool all_normal(const Gateway& gateway) {
    for (const auto& m : gateway.machines())
        if (m.state != AdapterState::normal) return false;
    return true;
}

bool answers(Client& client, const std::string& guid) {
    auto values = client.query(guid, {QueryItem{"pos", std::nullopt}});
    return values.ok() && values->size() == 1 && (*values)[0].status.ok;
}

std::optional<std::string> retained_state(Inbox& inbox, const std::string& guid) {
    std::lock_guard<std::mutex> lock(inbox.mutex);
    std::optional<std::string> last;
    for (const auto& m : inbox.messages)
        if (m.topic == topics::notify_state(guid) && !m.payload.empty())
            if (auto n = decode<NotifyState>(m.payload)) last = n->state;
    return last;
}

}  // namespace

TEST_CASE("gateway: 20 machines each answer Query as their own GUID and one removed goes offline alone") {
    MosquittoBroker broker;
    GatewayConfig config;
    config.mqtt_client = GENERATE(as<std::string>{}, "mosquitto", "paho");
    INFO("mqtt_client " << config.mqtt_client);
    for (int i = 0; i < 20; ++i) config.machines.push_back(machine(broker, i));
    Gateway gateway(config, fake_drivers());
    REQUIRE(gateway.start().ok());
    REQUIRE(gateway.machines().size() == 20);
    REQUIRE(eventually([&] { return all_normal(gateway); }, 60s));

    auto client = started_client(broker.url(), "gw-app", 10s);
    for (int i = 0; i < 20; ++i) CHECK(answers(*client, fmt::format("gw-{:02d}", i)));

    // Every machine's state as the broker keeps it (retained Notify/State).
    MqttOptions o;
    o.broker_url = broker.url();
    o.client_id = "gw-watcher";
    auto watcher = make_mqtt_transport(o).value();
    Inbox inbox;
    inbox.attach(*watcher);
    REQUIRE(watcher->subscribe({topics::notify_state("+")}, 1).ok());
    REQUIRE(watcher->start().ok());
    REQUIRE(eventually([&] { return retained_state(inbox, "gw-19") == std::optional<std::string>("online"); }, 20s));

    REQUIRE(gateway.remove_machine("gw-07").ok());
    CHECK(gateway.machines().size() == 19);
    CHECK_FALSE(gateway.machine("gw-07"));
    REQUIRE(eventually([&] { return retained_state(inbox, "gw-07") == std::optional<std::string>("offline"); }, 20s));
    CHECK(retained_state(inbox, "gw-06") == std::optional<std::string>("online"));
    for (int i : {0, 6, 8, 19}) CHECK(answers(*client, fmt::format("gw-{:02d}", i)));
    CHECK_FALSE(gateway.remove_machine("gw-07").ok());  // 401: gone already

    // Back at run time; a second machine with its GUID is refused.
    REQUIRE(gateway.add_machine(machine(broker, 7)).ok());
    auto twin = machine(broker, 7);
    twin.id = "twin";
    const auto refused = gateway.add_machine(twin);
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::keys_of_arguments);
    REQUIRE(eventually([&] { return retained_state(inbox, "gw-07") == std::optional<std::string>("online"); }, 20s));
    CHECK(eventually([&] { return answers(*client, "gw-07"); }, 20s));

    gateway.stop();
    CHECK(eventually([&] { return retained_state(inbox, "gw-19") == std::optional<std::string>("offline"); }, 20s));
    watcher->stop();
}

TEST_CASE("gateway: a machine that cannot start is named and the others serve") {
    MosquittoBroker broker;
    GatewayConfig config;
    config.machines.push_back(machine(broker, 0));
    auto broken = machine(broker, 1);
    broken.adapter.model_path = "/nonexistent/model.json";
    config.machines.push_back(broken);
    Gateway gateway(config, fake_drivers());
    const auto started = gateway.start();
    REQUIRE_FALSE(started.ok());
    CHECK(started.error().message.find("gw-01") != std::string::npos);
    REQUIRE(gateway.machines().size() == 1);
    auto client = started_client(broker.url(), "gw-app2", 10s);
    CHECK(eventually([&] { return answers(*client, "gw-00"); }, 20s));
}

TEST_CASE("gateway reload: removed, added, a changed machine restarted alone, a log level applied in place") {
    MosquittoBroker broker;
    GatewayConfig config;
    for (int i = 0; i < 4; ++i) config.machines.push_back(machine(broker, i));
    Gateway gateway(config, fake_drivers());
    REQUIRE(gateway.start().ok());
    REQUIRE(eventually([&] { return all_normal(gateway); }, 60s));
    const auto kept = gateway.machine("gw-00");
    const auto quieter = gateway.machine("gw-01");
    const auto changed = gateway.machine("gw-02");

    GatewayConfig next;
    next.machines.push_back(machine(broker, 0));  // unchanged
    next.machines.push_back(machine(broker, 1));  // log level only
    next.machines.back().adapter.log_level = LogLevel::warn;
    next.machines.push_back(machine(broker, 2));  // a key only a start applies
    next.machines.back().adapter.sampling.enabled = !next.machines.back().adapter.sampling.enabled;
    next.machines.push_back(machine(broker, 4));  // new; gw-03 is no longer listed
    auto broken = machine(broker, 5);             // new, and cannot start
    broken.adapter.model_path = "/no/such/model.json";
    next.machines.push_back(broken);

    const GatewayReload report = gateway.reload(next);
    CHECK(report.removed == std::vector<std::string>{"gw-03"});
    CHECK(report.added == std::vector<std::string>{"gw-04"});
    CHECK(report.restarted == std::vector<std::string>{"gw-02"});
    CHECK(report.applied == std::vector<std::string>{"gw-01"});
    REQUIRE(report.errors.size() == 1);
    CHECK_THAT(report.errors[0], Catch::Contains("gw-05"));

    CHECK(gateway.machine("gw-00") == kept);     // not touched
    CHECK(gateway.machine("gw-01") == quieter);  // reloaded in place
    CHECK(gateway.machine("gw-02") != changed);  // a new adapter
    CHECK_FALSE(gateway.machine("gw-03"));
    CHECK(gateway.machines().size() == 4);

    auto client = started_client(broker.url(), "gw-reload-app", 10s);
    for (int i : {0, 1, 2, 4}) CHECK(eventually([&] { return answers(*client, fmt::format("gw-{:02d}", i)); }, 20s));

    // The same file again changes nothing.
    GatewayConfig same;
    for (const auto& m : next.machines)
        if (m.id != "gw-05") same.machines.push_back(m);
    const GatewayReload quiet = gateway.reload(same);
    CHECK(quiet.added.empty());
    CHECK(quiet.removed.empty());
    CHECK(quiet.restarted.empty());
    CHECK(quiet.applied.empty());
    gateway.stop();
}

namespace {
// The process's threads by name (what `top -H` shows).
std::map<std::string, std::size_t> threads_in_process() {
    std::map<std::string, std::size_t> names;
    for (const auto& e : std::filesystem::directory_iterator("/proc/self/task")) {
        std::ifstream comm(e.path() / "comm");
        std::string name;
        std::getline(comm, name);
        ++names[name];
    }
    return names;
}

std::size_t count(const std::map<std::string, std::size_t>& names) {
    std::size_t n = 0;
    for (const auto& [name, k] : names) n += k;
    return n;
}

std::string added_names(const std::map<std::string, std::size_t>& before, const std::map<std::string, std::size_t>& after) {
    std::string out;
    for (const auto& [name, k] : after) {
        const auto was = before.count(name) ? before.at(name) : 0;
        if (k > was) out += fmt::format("{}{} x{}", out.empty() ? "" : ", ", name, k - was);
    }
    return out;
}
}  // namespace

TEST_CASE("gateway: machines share the timer, request and driver threads, and each still samples") {
    MosquittoBroker broker;
    GatewayConfig config;
    config.timer_threads = 2;
    config.request_threads = 2;
    config.driver_threads = 2;
    constexpr int kMachines = 20;
    for (int i = 0; i < kMachines; ++i) config.machines.push_back(machine(broker, i));
    // TSan's runtime starts a thread of its own with the process's first
    // thread: one started and joined here puts it in `before`.
    std::thread([] {}).join();
    const auto before = threads_in_process();
    Gateway gateway(config, fake_drivers());
    REQUIRE(gateway.start().ok());
    REQUIRE(eventually([&] { return all_normal(gateway); }, 60s));
    // Shared: 2 timer + 2 request + 2 driver threads + the watchdog + the
    // machines' one MQTT I/O thread. Each machine adds its connection's
    // sender, its events engine, its method ticker and its sample spool,
    // which all sleep while idle. With threads of their own it was 12 each;
    // with mqtt_client "paho" each machine an MQTT I/O thread of its own more.
    const auto after = threads_in_process();
    const std::size_t added = count(after) - count(before);
    INFO("threads added by the gateway: " << added << " (" << added_names(before, after) << ")");
    CHECK(added <= 8 + 4 * kMachines);

    // Every machine's channel delivers Sample DTUs, sampled on the shared timers.
    MqttOptions o;
    o.broker_url = broker.url();
    o.client_id = "gw-samples";
    auto watcher = make_mqtt_transport(o).value();
    Inbox inbox;
    inbox.attach(*watcher);
    REQUIRE(watcher->subscribe({"Sample/+/ch1"}, 0).ok());
    REQUIRE(watcher->start().ok());
    REQUIRE(eventually(
        [&] {
            std::set<std::string> seen;
            std::lock_guard<std::mutex> lock(inbox.mutex);
            for (const auto& m : inbox.messages)
                if (auto d = decode<SampleDtu>(m.payload)) seen.insert(d->guid);
            return seen.size() == kMachines;
        },
        30s));
    // Not all at the same instant: each machine's rows sit at its own place
    // in the 10 ms interval (SharedThreads gives out phases 0, 1/2, 1/4, ...).
    // On one grid every beginTime would share its residue modulo 10 ms, give
    // or take the millisecond the wall clock is truncated to.
    {
        std::map<std::string, std::int64_t> residue;
        std::lock_guard<std::mutex> lock(inbox.mutex);
        for (const auto& m : inbox.messages)
            if (auto d = decode<SampleDtu>(m.payload)) residue.emplace(d->guid, d->begin_time % 10);
        std::set<std::int64_t> places;
        for (const auto& [guid, r] : residue) places.insert(r);
        INFO("residues of beginTime modulo the 10 ms interval: " << places.size());
        CHECK(places.size() >= 5);
    }
    // Requests and driver calls of every machine on the shared workers.
    auto client = started_client(broker.url(), "gw-app-shared", 10s);
    for (int i = 0; i < kMachines; ++i) CHECK(answers(*client, fmt::format("gw-{:02d}", i)));
    gateway.stop();
    watcher->stop();
}

TEST_CASE("gateway: machines of one model file share one parsed model, each still its own terminal") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-gw-models-");
    std::filesystem::create_directories(dir.path);
    const auto other_model = (dir.path / "other.json").string();
    std::filesystem::copy_file(test_model_path(), other_model);
    GatewayConfig config;
    for (int i = 0; i < 4; ++i) config.machines.push_back(machine(broker, i));
    config.machines[3].adapter.model_path = other_model;  // the same content, another file
    Gateway gateway(config, fake_drivers());
    REQUIRE(gateway.start().ok());
    REQUIRE(eventually([&] { return all_normal(gateway); }, 60s));

    const auto model_of = [&](int i) { return gateway.machine(fmt::format("gw-{:02d}", i))->model(); };
    REQUIRE(model_of(0));
    CHECK(model_of(1).get() == model_of(0).get());
    CHECK(model_of(2).get() == model_of(0).get());
    CHECK(model_of(3).get() != model_of(0).get());
    CHECK(*model_of(3) == *model_of(0));

    auto client = started_client(broker.url(), "gw-models-app", 10s);
    for (int i = 0; i < 4; ++i) CHECK(answers(*client, fmt::format("gw-{:02d}", i)));
    // A machine removed and added back finds the model still in use by the
    // others, not a parse of its own.
    REQUIRE(gateway.remove_machine("gw-01").ok());
    REQUIRE(gateway.add_machine(machine(broker, 1)).ok());
    REQUIRE(eventually([&] { return all_normal(gateway); }, 30s));
    CHECK(model_of(1).get() == model_of(0).get());
    CHECK(eventually([&] { return answers(*client, "gw-01"); }, 20s));
    client->stop();
    gateway.stop();
}
