// The agent against a real mosquitto: a real adapter (fake driver) and the
// client library around it; several agent instances on shared subscriptions
// and split by terminal id without them;
// the generated ACL file enforced by the broker.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/paho_transport.hpp>

#include "support/ack_dropping_proxy.hpp"
#include "support/inbox.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/mqtt5_refusing_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"
#include "support/adapter_fixture.hpp"  // FakeDriver, scratch_dir, test_model_path

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>

extern char** environ;

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

/// Starts a program with its output discarded; its pid, or -1.
pid_t spawn_program(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    for (int fd : {0, 1, 2}) posix_spawn_file_actions_addopen(&actions, fd, "/dev/null", O_RDWR, 0);
    pid_t pid = -1;
    if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&actions);
    return pid;
}

/// A broker enforcing the mosquitto ACL the agent writes for `c` (in `dir`).
MosquittoOptions acl_broker(const AgentConfig& c, const std::string& dir) {
    const std::string acl = dir + "/acl";
    std::ofstream(acl) << mosquitto_acl(c);
    MosquittoOptions options;
    options.acl_file = acl;
    return options;
}

AgentConfig agent_config(const MosquittoBroker& broker, const std::string& name = "agent-a") {
    AgentConfig c;
    c.broker_url = broker.url();
    c.client_id = name;
    c.request_timeout = 400ms;
    return c;
}

std::unique_ptr<Agent> start_agent(AgentConfig c) {
    auto agent = std::make_unique<Agent>(std::move(c));
    REQUIRE(agent->start().ok());
    REQUIRE(eventually([&] { return agent->stats().transport.connects >= 1; }));
    std::this_thread::sleep_for(200ms);  // SUBACKs come asynchronously
    return agent;
}

std::unique_ptr<Adapter> start_adapter(const MosquittoBroker& broker, std::shared_ptr<FakeDriver> driver,
                                       const std::string& username = "") {
    AdapterConfig c;
    c.model_path = test_model_path();
    c.broker_url = broker.url();
    c.username = username;
    c.register_timeout = 300ms;
    return started_adapter(c, std::move(driver));
}

std::unique_ptr<Client> start_client(const MosquittoBroker& broker, const std::string& ex, const std::string& username = "") {
    auto c = started_client(broker.url(), ex, 2000ms, [&](MqttOptions& m, ClientOptions&) { m.username = username; });
    std::this_thread::sleep_for(100ms);
    return c;
}

/// The agent serves: the test adapter registers, an application `ex`
/// registers too and Discovery lists the adapter. The client is returned
/// for more checks.
std::unique_ptr<Client> expect_served(const MosquittoBroker& broker, const Adapter& adapter, const std::string& ex) {
    REQUIRE(eventually([&] { return adapter.stats().registered; }));
    auto client = start_client(broker, ex);
    auto registered = client->register_terminal();
    REQUIRE(registered.ok());
    CHECK(registered->kind == RegisterOutcome::Kind::accepted);
    auto list = client->discover();
    REQUIRE(list.ok());
    REQUIRE(list->size() == 1);
    CHECK((*list)[0].guid == "test-dev");
    return client;
}

/// A raw MQTT peer collecting what arrives on its subscriptions.
struct Peer {
    Peer(const MosquittoBroker& broker, const std::string& id, std::vector<std::string> filters, const std::string& username = "",
         int version = 4) {
        MqttOptions m;
        m.broker_url = broker.url();
        m.client_id = id;
        m.username = username;
        m.mqtt_version = version;
        transport = make_mqtt_transport(m).value();
        inbox.attach(*transport);
        REQUIRE(transport->subscribe(filters, 1).ok());
        REQUIRE(transport->start().ok());
        REQUIRE(eventually([&] { return transport->state() == LinkState::connected; }));
        std::this_thread::sleep_for(150ms);
    }
    void send(const std::string& topic, const Json& payload) {
        REQUIRE(transport->publish(Message{topic, payload.dump(), 1, false}).ok());
    }
    std::vector<Json> on(const std::string& topic) {
        std::lock_guard<std::mutex> lock(inbox.mutex);
        std::vector<Json> out;
        for (const auto& m : inbox.messages)
            if (m.topic == topic) out.push_back(Json::parse(m.payload));
        return out;
    }
    std::unique_ptr<Transport> transport;
    Inbox inbox;  // destroyed first: it stops the transport, which then goes
};

}  // namespace

TEST_CASE("agent with adapter and client: register and discover and cached probe and DEV_UNREACHABLE") {
    MosquittoBroker broker;
    AgentConfig c = agent_config(broker);
    c.state_dir = scratch_dir("itest-agent");
    auto agent = start_agent(c);
    auto driver = std::make_shared<FakeDriver>();
    auto adapter = start_adapter(broker, driver);
    auto client = expect_served(broker, *adapter, "mes-1");
    REQUIRE(eventually([&] { return agent->cached_model("test-dev").has_value(); }));
    auto list = client->discover();
    REQUIRE(list.ok());
    REQUIRE(list->size() == 1);
    CHECK((*list)[0].status == "online");

    // live: the adapter answers, the agent only watches
    auto values = client->query("test-dev", {QueryItem{"pos", std::nullopt}});
    REQUIRE(values.ok());
    CHECK((*values)[0].status.ok);
    CHECK(agent->stats().timeouts == 0);

    adapter->stop();
    REQUIRE(eventually([&] {
        for (const auto& t : agent->terminals())
            if (t.id == "test-dev") return t.status == "offline";
        return false;
    }));
    auto model = client->probe("test-dev");
    REQUIRE(model.ok());
    CHECK((*model)["devices"][0]["guid"] == "test-dev");
    auto unreachable = client->query("test-dev", {QueryItem{"pos", std::nullopt}});
    REQUIRE_FALSE(unreachable.ok());
    CHECK(unreachable.error().code == ErrorCode::unavailable);
    CHECK(unreachable.error().message.find("DEV_UNREACHABLE") != std::string::npos);
    CHECK(client->stats().unreachable == 1);

    // a restarted agent still knows the adapter and its model
    agent->stop();
    agent = start_agent(c);
    list = client->discover();
    REQUIRE(list.ok());
    REQUIRE(list->size() == 1);
    CHECK((*list)[0].status == "offline");
    REQUIRE(client->probe("test-dev").ok());
    client->stop();
    agent->stop();
    std::filesystem::remove_all(c.state_dir);
}

TEST_CASE("agent: a request the adapter does not answer in time gets 203") {
    MosquittoBroker broker;
    auto agent = start_agent(agent_config(broker));
    auto driver = std::make_shared<FakeDriver>();
    auto adapter = start_adapter(broker, driver);
    auto client = start_client(broker, "mes-1");
    driver->delay = 900ms;  // the adapter's driver deadline is 1000 ms; the agent's 400 ms
    auto slow = client->query("test-dev", {QueryItem{"pos", std::nullopt}});
    REQUIRE_FALSE(slow.ok());
    CHECK(slow.error().code == ErrorCode::timeout);
    CHECK(agent->stats().timeouts == 1);
    driver->delay = 0ms;
    REQUIRE(eventually([&] { return client->stats().unmatched_responses >= 1; }));  // the adapter answered after the agent
}

TEST_CASE("two agents on shared subscriptions answer once") {
    for (int version : {5, 4}) {
        DYNAMIC_SECTION("MQTT version " << version) {
            MosquittoBroker broker;
            AgentConfig a = agent_config(broker, "agent-a");
            AgentConfig b = agent_config(broker, "agent-b");
            a.mqtt_version = b.mqtt_version = version;
            auto first = start_agent(a);
            auto second = start_agent(b);
            Peer app(broker, "app",
                     {"Register/Response/+", "Discovery/Response/+", "Query/Response/+/+", "Probe/Version/Response/+"});
            for (int i = 0; i < 6; ++i) {
                app.send("Register/Request", Json{{"@id", "r" + std::to_string(i)}, {"cli_uuid", "t" + std::to_string(i)}});
                app.send("Discovery/Request/app", Json{{"@id", "d" + std::to_string(i)}, {"guid", "app"}});
                app.send("Query/Request/silent/app", Json{{"@id", "q" + std::to_string(i)}, {"ids", {"pos"}}});
            }
            REQUIRE(eventually([&] { return app.on("Query/Response/silent/app").size() >= 6; }));
            std::this_thread::sleep_for(600ms);  // room for a second answer to show up
            std::size_t registers = 0;
            for (int i = 0; i < 6; ++i) registers += app.on("Register/Response/t" + std::to_string(i)).size();
            CHECK(registers == 6);
            CHECK(app.on("Discovery/Response/app").size() == 6);
            CHECK(app.on("Query/Response/silent/app").size() == 6);
            CHECK(first->stats().registrations + second->stats().registrations == 6);
            CHECK(first->stats().timeouts + second->stats().timeouts == 6);
            // both learned every registration (from each other's answers)
            REQUIRE(eventually([&] {
                std::size_t known = 0;
                for (const auto& t : second->terminals()) known += t.registered ? 1 : 0;
                for (const auto& t : first->terminals()) known += t.registered ? 1 : 0;
                return known == 12;
            }));
        }
    }
}

// Where the broker has no $share (RabbitMQ 3.10): every instance subscribes
// plainly and answers only the requests of its share (instance_split.hpp).
TEST_CASE("two agents without $share split the requests by terminal and answer once") {
    MosquittoBroker broker;
    AgentConfig configs[2] = {agent_config(broker, "agent-a"), agent_config(broker, "agent-b")};
    for (unsigned k = 0; k < 2; ++k) {
        configs[k].mqtt_version = 4;  // as on RabbitMQ
        configs[k].share_group = "";
        configs[k].instances = 2;
        configs[k].instance = k;
    }
    std::unique_ptr<Agent> agents[2] = {start_agent(configs[0]), start_agent(configs[1])};
    Peer app(broker, "app", {"Register/Response/+", "Discovery/Response/+", "Query/Response/+/+", "Probe/Version/Response/+"});
    const int n = 8;
    auto id = [](const char* prefix, int i) { return prefix + std::to_string(i); };
    for (int i = 0; i < n; ++i) {
        app.send("Register/Request", Json{{"@id", id("r", i)}, {"cli_uuid", id("t", i)}});
        app.send("Discovery/Request/" + id("app", i), Json{{"@id", id("d", i)}, {"guid", id("app", i)}});
        app.send("Query/Request/" + id("silent", i) + "/app", Json{{"@id", id("q", i)}, {"ids", {"pos"}}});
        app.send("Probe/Version/" + id("dev", i), Json{{"@id", id("v", i)}, {"guid", id("dev", i)}, {"version", "1"}});
    }
    REQUIRE(eventually([&] {
        for (int i = 0; i < n; ++i)
            if (app.on("Query/Response/" + id("silent", i) + "/app").empty()) return false;
        return true;
    }));
    std::this_thread::sleep_for(600ms);  // room for a second answer to show up
    for (int i = 0; i < n; ++i) {
        INFO(i);
        CHECK(app.on("Register/Response/" + id("t", i)).size() == 1);
        CHECK(app.on("Discovery/Response/" + id("app", i)).size() == 1);
        CHECK(app.on("Query/Response/" + id("silent", i) + "/app").size() == 1);
        CHECK(app.on("Probe/Version/Response/" + id("dev", i)).size() == 1);
    }
    const AgentStats s0 = agents[0]->stats(), s1 = agents[1]->stats();
    CHECK(s0.registrations + s1.registrations == n);
    CHECK(s0.discoveries + s1.discoveries == n);
    CHECK(s0.timeouts + s1.timeouts == n);
    CHECK(s0.versions + s1.versions == n);
    // Both answered some of each kind: the ids t0..t7, app0..7, silent0..7
    // and dev0..7 fall half to each (FNV-1a 32 mod 2).
    for (const AgentStats& s : {s0, s1}) {
        CHECK(s.registrations == n / 2);
        CHECK(s.discoveries == n / 2);
        CHECK(s.timeouts == n / 2);
        CHECK(s.versions == n / 2);
    }
    // Each watched the other's Register/Response: both know every registration.
    REQUIRE(eventually([&] {
        std::size_t known = 0;
        for (auto& agent : agents)
            for (const auto& t : agent->terminals()) known += t.registered ? 1 : 0;
        return known == 2 * n;
    }));

    // No takeover: with instance 1 gone, its share is not answered until it is back.
    agents[1]->stop();
    for (int i = 0; i < n; ++i) app.send("Register/Request", Json{{"@id", id("again", i)}, {"cli_uuid", id("t", i)}});
    REQUIRE(eventually([&] {
        std::size_t answered = 0;
        for (int i = 0; i < n; ++i) answered += app.on("Register/Response/" + id("t", i)).size();
        return answered >= n + n / 2;
    }));
    std::this_thread::sleep_for(600ms);
    std::size_t answered = 0;
    for (int i = 0; i < n; ++i) answered += app.on("Register/Response/" + id("t", i)).size();
    CHECK(answered == n + n / 2);
    agents[1] = start_agent(configs[1]);
    for (int i = 0; i < n; ++i) app.send("Register/Request", Json{{"@id", id("back", i)}, {"cli_uuid", id("t", i)}});
    REQUIRE(eventually([&] {
        std::size_t all = 0;
        for (int i = 0; i < n; ++i) all += app.on("Register/Response/" + id("t", i)).size();
        return all == n + n / 2 + n;  // instance 1 answers again
    }));
}

// RabbitMQ 3.10 closes an MQTT 5 CONNECT without a CONNACK (docs/scaling.md):
// here a proxy in front of mosquitto does the same and passes 3.1.1 through.
TEST_CASE("an agent with mqtt_version auto behind a broker that refuses MQTT 5 falls back to 3.1.1 and serves") {
    MosquittoBroker broker;
    Mqtt5RefusingBroker refusing(broker.port());
    AgentConfig c = agent_config(broker, "agent-auto");
    c.broker_url = refusing.url();
    c.mqtt_version = 0;  // "auto"
    c.share_group = "";  // plain subscriptions, as on RabbitMQ
    auto agent = start_agent(c);
    // Its two connections (the main one and Discovery's) each try 5, then 4.
    const auto count = [&](int level) {
        const auto levels = refusing.levels();
        return std::count(levels.begin(), levels.end(), level);
    };
    REQUIRE(eventually([&] { return refusing.levels().size() >= 4; }));
    CHECK(count(5) == 2);
    CHECK(count(4) == 2);

    auto adapter = start_adapter(broker, std::make_shared<FakeDriver>());
    auto client = expect_served(broker, *adapter, "mes-auto");

    // A reconnection keeps 3.1.1 at once, on both.
    refusing.drop_clients();
    REQUIRE(eventually([&] { return agent->stats().transport.connects >= 2 && refusing.levels().size() >= 6; }));
    CHECK(refusing.levels().size() == 6);
    CHECK(count(5) == 2);
    CHECK(count(4) == 4);
    client->stop();
    adapter->stop();
    agent->stop();
}

TEST_CASE("an agent with mqtt_version auto speaks MQTT 5 to a broker that takes it, shared subscriptions and all") {
    MosquittoBroker broker;
    Mqtt5RefusingBroker recording(broker.port());
    recording.accept_mqtt5(true);
    AgentConfig c = agent_config(broker, "agent-auto-5");
    c.broker_url = recording.url();
    c.mqtt_version = 0;
    auto agent = start_agent(c);
    // The shared-subscription check's connection, then the agent's two.
    REQUIRE(eventually([&] { return recording.levels().size() >= 3; }));
    CHECK(recording.levels() == std::vector<int>{5, 5, 5});
    CHECK(agent->share_group_in_use() == "nclink-agent");
    auto client = start_client(broker, "mes-auto-5");
    auto registered = client->register_terminal();
    REQUIRE(registered.ok());
    CHECK(registered->kind == RegisterOutcome::Kind::accepted);
    client->stop();
    agent->stop();
}

// A broker without shared subscriptions (docs/scaling.md): ejabberd 23.01
// ends the connection at a SUBSCRIBE to $share/..., RabbitMQ 3.10 delivers
// nothing to it. An agent with the default share group used to register
// nobody on either; it now checks at start, on a connection of its own,
// and answers through plain subscriptions.
TEST_CASE("an agent with the default share group on a broker without $share answers through plain subscriptions") {
    for (const bool close : {true, false}) {
        DYNAMIC_SECTION((close ? "the broker ends the connection at the SUBSCRIBE" : "the broker delivers nothing")) {
            MosquittoBroker broker;
            AckDroppingProxy proxy(broker.port());
            proxy.refuse_shared_subscriptions(close);
            AgentConfig c = agent_config(broker, "agent-no-share");
            c.broker_url = proxy.url();
            REQUIRE(c.share_group == "nclink-agent");  // the default
            auto agent = start_agent(c);
            CHECK(agent->share_group_in_use().empty());
            CHECK(proxy.shares_refused() == 1);  // the check's SUBSCRIBE only

            auto adapter = start_adapter(broker, std::make_shared<FakeDriver>());
            auto client = expect_served(broker, *adapter, "mes-no-share");
            // Its own connection was never dropped for a $share filter.
            CHECK(agent->stats().transport.connects == 1);
            CHECK(proxy.shares_refused() == 1);
            client->stop();
            adapter->stop();
            agent->stop();
        }
    }
}

TEST_CASE("an agent whose broker has shared subscriptions keeps its share group") {
    MosquittoBroker broker;
    AckDroppingProxy proxy(broker.port());  // passes everything
    AgentConfig c = agent_config(broker, "agent-share");
    c.broker_url = proxy.url();
    auto agent = start_agent(c);
    CHECK(agent->share_group_in_use() == "nclink-agent");
    // The check's connection and the agent's two (main and Discovery).
    REQUIRE(eventually([&] { return proxy.connections() >= 3; }));
    CHECK(proxy.connections() == 3);
    agent->stop();
}

// At 10,000 machines starting together the agent's main connection is
// queued tens of seconds deep (docs/performance.md); here its main link is
// held outright. Discovery, on its own connection, is still answered, from
// what the agent knew, while a registration waits on the held link.
TEST_CASE("an agent answers Discovery on its Discovery link while its main link is held") {
    MosquittoBroker broker;
    AckDroppingProxy proxy(broker.port());
    auto agent = std::make_unique<Agent>(agent_config(broker, "agent-two-links"));
    MqttOptions main_link;
    main_link.broker_url = proxy.url();
    main_link.client_id = "agent-two-links";
    MqttOptions discovery_link;
    discovery_link.broker_url = broker.url();
    discovery_link.client_id = "agent-two-links-discovery";
    agent->use_transport(make_paho_transport(main_link).value());
    agent->use_discovery_transport(make_paho_transport(discovery_link).value());
    REQUIRE(agent->start().ok());
    REQUIRE(eventually([&] { return agent->stats().transport.connects >= 1; }));
    std::this_thread::sleep_for(200ms);  // SUBACKs come asynchronously

    auto adapter = start_adapter(broker, std::make_shared<FakeDriver>());
    auto client = expect_served(broker, *adapter, "mes-two-links");
    proxy.hold_now();
    auto late = start_client(broker, "mes-late");
    RequestOptions quick;
    quick.timeout = 500ms;
    auto unanswered = late->register_terminal(quick);
    REQUIRE(unanswered.ok());
    CHECK(unanswered->kind == RegisterOutcome::Kind::no_answer);  // the main link hears nothing now
    auto list = client->discover();
    REQUIRE(list.ok());
    REQUIRE(list->size() == 1);
    CHECK((*list)[0].guid == "test-dev");
    CHECK(agent->stats().discoveries == 2);
    proxy.release();
    late->stop();
    client->stop();
    adapter->stop();
    agent->stop();
}

// adapter_liveness_ms on a broker whose wills may not come (a cluster node
// that dies, a link that hangs): the agent asks a silent adapter for its
// model before it says offline, so a quiet adapter stays online and one
// behind a hung link goes offline without its will (docs/agent.md).
TEST_CASE("an agent asks a silent adapter before it says offline, and says so for one behind a hung link") {
    MosquittoBroker broker;
    AckDroppingProxy proxy(broker.port());
    AgentConfig c = agent_config(broker, "agent-liveness");
    c.adapter_liveness = 1000ms;
    c.request_timeout = 400ms;
    c.observe_samples = false;  // the adapter's samples would keep it heard
    auto agent = start_agent(c);

    AdapterConfig a;
    a.model_path = test_model_path();
    a.broker_url = proxy.url();
    a.keep_alive = 60s;  // the broker keeps the hung link, and the will, for 90 s
    a.register_timeout = 300ms;
    auto adapter = started_adapter(a, std::make_shared<FakeDriver>());
    REQUIRE(eventually([&] { return adapter->stats().registered; }));
    const auto status = [&] {
        for (const auto& t : agent->terminals())
            if (t.id == "test-dev") return t.status;
        return std::string();
    };
    REQUIRE(eventually([&] { return status() == "online"; }));

    // Quiet but there (the agent does not watch its samples): asked, answers,
    // stays online through three liveness periods.
    const std::uint64_t requests_before = adapter->stats().requests;
    bool always_online = true;
    for (int i = 0; i < 30; ++i) {
        always_online = always_online && status() == "online";
        std::this_thread::sleep_for(100ms);
    }
    CHECK(always_online);
    CHECK(adapter->stats().requests >= requests_before + 2);

    // Behind a hung link: asked, no answer within the request timeout: offline,
    // while the broker still has it connected (no will published).
    proxy.hold_now();
    CHECK(eventually([&] { return status() == "offline"; }, 10s));
    auto client = start_client(broker, "mes-liveness");
    auto list = client->discover();
    REQUIRE(list.ok());
    REQUIRE(list->size() == 1);
    CHECK((*list)[0].status == "offline");
    CHECK(adapter->stats().transport.connects == 1);

    // The link passes again: its answer brings it back.
    proxy.release();
    CHECK(eventually([&] { return status() == "online"; }, 10s));
    client->stop();
    adapter->stop();
    agent->stop();
}

TEST_CASE("broker ACL from the agent's configuration keeps denied requests from the adapter") {
    AgentConfig c;
    c.access.applications["viewer"]["*"] = access_read;
    const std::string dir = scratch_dir("itest-acl");
    MosquittoBroker broker(acl_broker(c, dir));
    AgentConfig ac = agent_config(broker);
    ac.access = c.access;
    ac.username = "nclink-agent";
    auto agent = start_agent(ac);
    auto driver = std::make_shared<FakeDriver>();
    auto adapter = start_adapter(broker, driver, "test-dev");
    REQUIRE(eventually([&] { return adapter->stats().registered; }));  // the ACL lets registration through

    auto viewer = start_client(broker, "viewer", "viewer");
    auto mes = start_client(broker, "mes", "mes");
    const auto adapter_requests = adapter->stats().requests;

    // denied: the agent answers 301 and the adapter never sees the request
    auto denied = viewer->set("test-dev", {SetItem{"ovr", Json{{"value", 55}}, std::nullopt, std::nullopt}});
    REQUIRE_FALSE(denied.ok());
    CHECK(denied.error().code == ErrorCode::permission_denied);
    std::this_thread::sleep_for(300ms);
    CHECK(adapter->stats().requests == adapter_requests);
    CHECK(driver->writes == 0);
    CHECK(agent->stats().denied == 1);

    // allowed reading reaches the adapter
    auto read = viewer->query("test-dev", {QueryItem{"pos", std::nullopt}});
    REQUIRE(read.ok());
    CHECK((*read)[0].status.ok);

    // another application may set
    auto set = mes->set("test-dev", {SetItem{"ovr", Json{{"value", 55}}, std::nullopt, std::nullopt}});
    REQUIRE(set.ok());
    CHECK((*set)[0].status.ok);
    CHECK(driver->writes == 1);

    // posing as another application is stopped by the broker
    Peer spoof(broker, "viewer-2", {"Set/Response/+/+"}, "viewer");
    spoof.send("Set/Request/test-dev/mes", Json{{"@id", "x"}, {"values", {{{"id", "ovr"}, {"params", {{"value", 1}}}}}}});
    std::this_thread::sleep_for(400ms);
    CHECK(driver->writes == 1);
    viewer->stop();
    mes->stop();
    std::filesystem::remove_all(dir);
}

TEST_CASE("broker ACL passes other applications' method runs and events only to an application with watch") {
    AgentConfig c;
    c.access.default_rights = access_all;
    c.access.applications["dash"]["*"] = access_read | access_watch;
    c.access.applications["viewer"]["*"] = access_all;  // every request right, not watch
    c.registration.terminals["test-dev"] = TerminalEntry{"adapter", ""};
    const std::string dir = scratch_dir("itest-acl-watch");
    MosquittoBroker broker(acl_broker(c, dir));

    struct Watcher {
        std::mutex mutex;
        std::vector<std::string> seen;  // "kind ex"
        void add(std::string what) {
            std::lock_guard<std::mutex> lock(mutex);
            seen.push_back(std::move(what));
        }
        std::multiset<std::string> get() {
            std::lock_guard<std::mutex> lock(mutex);
            return {seen.begin(), seen.end()};
        }
    };
    auto watch = [](Client& client, Watcher& w) {
        REQUIRE(client
                    .subscribe_method_runs("test-dev",
                                           [&w](const MethodRun& r) { w.add(std::string(to_string(r.kind)) + " " + r.ex); })
                    .ok());
        REQUIRE(client.subscribe_events("test-dev", [&w](const WatchedEvent& e) { w.add("event " + e.ex); }).ok());
    };
    auto dash = start_client(broker, "dash", "dash");
    auto viewer = start_client(broker, "viewer", "viewer");
    Watcher dash_saw, viewer_saw;
    watch(*dash, dash_saw);
    watch(*viewer, viewer_saw);
    std::this_thread::sleep_for(300ms);  // the subscriptions are in place

    // The adapter answers a call of mes and one of viewer, and fires an event of mes.
    Peer adapter(broker, "test-dev", {}, "test-dev");
    adapter.send("Method/Status/test-dev/mes", Json{{"@id", "c1"}, {"id", "home"}, {"status", "executing"}, {"progress", 10}});
    adapter.send("Method/Result/test-dev/mes", Json{{"@id", "c1"}, {"id", "home"}, {"result", "finished"}, {"code", "OK"}});
    adapter.send("Event/test-dev/mes", Json{{"@id", "e1"}, {"id", "ev1"}, {"time", 1}, {"event", {{"id", "ovr"}, {"value", 120}}}});
    adapter.send("Method/Result/test-dev/viewer", Json{{"@id", "c2"}, {"id", "home"}, {"result", "finished"}, {"code", "OK"}});

    const std::multiset<std::string> everything = {"status mes", "result mes", "event mes", "result viewer"};
    REQUIRE(eventually([&] { return dash_saw.get() == everything; }, 10s));
    REQUIRE(eventually([&] { return viewer_saw.get().count("result viewer") == 1; }, 10s));
    std::this_thread::sleep_for(500ms);  // room for anything the broker should not have passed
    CHECK(dash_saw.get() == everything);
    CHECK(viewer_saw.get() == std::multiset<std::string>{"result viewer"});  // its own only
    dash->stop();
    viewer->stop();
    std::filesystem::remove_all(dir);
}

TEST_CASE("two agents on shared subscriptions: one killed and registrations and discovery stay correct") {
    MosquittoBroker broker;
    // The first agent is a real nclink-agent process, so it can die abruptly.
    const std::string binary = std::string(NCLINK_BINARY_DIR) + "/bin/nclink-agent";
    const pid_t killed = spawn_program({binary, "--broker", broker.url(), "--log-level", "warn"});
    REQUIRE(killed > 0);
    auto survivor = start_agent(agent_config(broker, "agent-b"));
    Peer app(broker, "app", {"Register/Response/+", "Discovery/Response/+"});
    std::this_thread::sleep_for(1500ms);  // the process has connected and subscribed
    // A request the broker handed to an agent the moment it died is lost
    // with it (MQTT shared subscriptions do not hand it to another member):
    // like any application, this one asks again after a timeout (2 s).
    auto register_terminals = [&](int from, int to) {
        auto send = [&](int i) {
            const std::string tid = "t" + std::to_string(i);
            app.send("Register/Request", Json{{"@id", "r" + tid}, {"cli_uuid", tid}});
            app.send("Probe/Version/" + tid, Json{{"@id", "v" + tid}, {"version", "1"}});
        };
        for (int i = from; i < to; ++i) send(i);
        auto asked = std::chrono::steady_clock::now();
        return eventually(
            [&] {
                bool all = true;
                const bool again = std::chrono::steady_clock::now() - asked > 2s;
                for (int i = from; i < to; ++i)
                    if (app.on("Register/Response/t" + std::to_string(i)).empty()) {
                        all = false;
                        if (again) send(i);
                    }
                if (again) asked = std::chrono::steady_clock::now();
                return all;
            },
            20s);
    };
    REQUIRE(register_terminals(0, 8));
    const auto before = survivor->stats().registrations;
    CHECK(before < 8);  // the process answered some of them

    ::kill(killed, SIGKILL);
    int status = 0;
    ::waitpid(killed, &status, 0);

    REQUIRE(register_terminals(8, 16));
    CHECK(survivor->stats().registrations == before + 8);  // all new ones by the survivor
    for (int i = 0; i < 4; ++i) app.send("Discovery/Request/app", Json{{"@id", "d" + std::to_string(i)}, {"guid", "app"}});
    REQUIRE(eventually([&] { return app.on("Discovery/Response/app").size() == 4; }, 20s));
    const Json last = app.on("Discovery/Response/app").back();
    REQUIRE(last.contains("deviceList"));
    std::set<std::string> listed;
    for (const auto& entry : last["deviceList"]) listed.insert(entry["guid"].get<std::string>());
    CHECK(listed.size() == 16);  // also those the dead agent registered: the survivor watched its answers
}
