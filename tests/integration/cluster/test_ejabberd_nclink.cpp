// nclink on an ejabberd cluster (Debian's 23.01, mod_mqtt), with the
// settings docs/scaling.md gives for it: every program logs in (the broker
// section's "username"/"password"; mod_mqtt refuses a CONNECT without a
// password), MQTT 5 or "auto" (ejabberd takes 5), and an agent with plain
// subscriptions (share_group ""): mod_mqtt closes the connection at a
// SUBSCRIBE to $share/....
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver
#include "support/patient_query.hpp"

#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

AdapterConfig adapter_config(const EjabberdCluster& ejabberd, int node, const std::string& id) {
    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = scratch_dir(id);
    config.broker_url = ejabberd.url(node);
    config.client_id = id;
    config.username = EjabberdCluster::username();
    config.password = EjabberdCluster::password();
    config.mqtt_version = 0;  // "auto": ejabberd accepts the MQTT 5 CONNECT
    config.register_timeout = 300ms;
    return config;
}

MqttOptions client_mqtt(const EjabberdCluster& ejabberd, int node) {
    MqttOptions mqtt;
    mqtt.broker_url = ejabberd.url(node);
    mqtt.mqtt_version = 5;
    mqtt.username = EjabberdCluster::username();
    mqtt.password = EjabberdCluster::password();
    return mqtt;
}

AgentConfig agent_config(const EjabberdCluster& ejabberd, int node, const std::string& id) {
    AgentConfig config;
    config.broker_url = ejabberd.url(node);
    config.client_id = id;
    config.username = EjabberdCluster::username();
    config.password = EjabberdCluster::password();
    config.mqtt_version = 5;
    return config;
}

}  // namespace

TEST_CASE("ejabberd cluster: an adapter on node 1 answers a Query from a client on node 2, logged in, on MQTT 5") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;

    AdapterConfig config = adapter_config(ejabberd, 0, "ej-adapter");
    auto driver = std::make_shared<FakeDriver>();
    Adapter adapter(config, driver, probe_logger());
    REQUIRE(adapter.start());
    REQUIRE(eventually([&] { return adapter.state() == AdapterState::normal; }, 60s));
    // "auto" got in with MQTT 5 at the first attempt.
    CHECK(adapter.stats().transport.connect_failures == 0);
    CHECK(adapter.stats().transport.connects == 1);

    // Without a login an adapter never gets in (CONNACK "not authorized").
    {
        AdapterConfig anonymous = config;
        anonymous.client_id = "ej-adapter-anonymous";
        anonymous.device_id.clear();
        anonymous.username.clear();
        anonymous.password.clear();
        anonymous.persistence_dir = scratch_dir("ej-adapter-anonymous");
        Adapter refused(anonymous, std::make_shared<FakeDriver>(), probe_logger());
        REQUIRE(refused.start());
        CHECK(eventually([&] { return refused.stats().transport.connect_failures >= 3; }, 30s));
        CHECK(refused.stats().transport.connects == 0);
        refused.stop();
        std::error_code ignored;
        std::filesystem::remove_all(anonymous.persistence_dir, ignored);
    }

    ClientOptions o;
    o.ex_cid = "ej-app";
    o.default_timeout = 300ms;  // the registration nobody answers (no agent here)
    auto made = Client::create(client_mqtt(ejabberd, 1), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);

    // The adapter's SUBSCRIBE is done by the time it is normal; asked again
    // all the same until answered, as on RabbitMQ.
    const auto asked = std::chrono::steady_clock::now();
    const auto answer = patient_query(client);
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - asked);
    REQUIRE(answer.size() == 2);
    REQUIRE(answer[0].values);
    CHECK(*answer[0].values == Json::array({12.5}));
    REQUIRE(answer[1].values);
    CHECK(*answer[1].values == Json::array({"running"}));
    std::printf("ejabberd: a Query from node 2 answered by the adapter on node 1 in %lld ms\n",
                static_cast<long long>(took.count()));

    client.stop();
    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}

// Agent on node 3, adapter on node 1, application on node 2.
TEST_CASE("ejabberd cluster: one agent with plain subscriptions registers an adapter and answers Discovery across nodes") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;

    AgentConfig agent_settings = agent_config(ejabberd, 2, "ej-agent");
    agent_settings.share_group = "";
    Agent agent(agent_settings, probe_logger());
    REQUIRE(agent.start());
    REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));

    AdapterConfig config = adapter_config(ejabberd, 0, "ej-agent-adapter");
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());
    // The agent's SUBSCRIBEs may still be on their way: the adapter asks again until accepted.
    CHECK(eventually([&] { return adapter.stats().registered; }, 60s));

    ClientOptions o;
    o.ex_cid = "ej-app";
    o.default_timeout = 3s;
    auto made = Client::create(client_mqtt(ejabberd, 1), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::accepted);

    CHECK(eventually(
        [&] {
            auto found = client.discover();
            if (!found) return false;
            for (const auto& entry : *found)
                if (entry.guid == "test-dev" && entry.status == "online") return true;
            return false;
        },
        30s));
    // The agent stayed on its one connection all along.
    CHECK(agent.stats().transport.connects == 1);

    client.stop();
    adapter.stop();
    agent.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}

// Several agents where the broker has no $share: "share_group" "" and
// "instances" 2 (docs/agent.md, "Without $share"), as on RabbitMQ. Agents on
// nodes 2 and 3, the application on node 1: every request is answered once,
// by the instance its terminal id hashes to (FNV-1a 32 mod 2: t0..t7 and
// app0..app7 fall half to each).
TEST_CASE("ejabberd cluster: two agents without $share split the requests by terminal and answer each once") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;

    std::unique_ptr<Agent> agents[2];
    for (unsigned k = 0; k < 2; ++k) {
        AgentConfig c = agent_config(ejabberd, 1 + static_cast<int>(k), "ej-agent-" + std::to_string(k));
        c.share_group = "";
        c.instances = 2;
        c.instance = k;
        agents[k] = std::make_unique<Agent>(c, probe_logger());
        REQUIRE(agents[k]->start());
        REQUIRE(eventually([&] { return agents[k]->stats().transport.connects >= 1; }, 30s));
    }
    Probe app(ejabberd.url(0), "ej-split-app", true, 4, EjabberdCluster::username(), EjabberdCluster::password());
    REQUIRE(app.connected());
    REQUIRE(app.subscribe_ready("Register/Response/+", "Register/Response/marker"));
    REQUIRE(app.subscribe_ready("Discovery/Response/+", "Discovery/Response/marker"));
    auto send = [&](const std::string& topic, const Json& payload) {
        REQUIRE(app.transport->publish(Message{topic, payload.dump(), 1, false}));
    };
    // The agents' SUBSCRIBEs may still be on their way: a registration of each
    // share (mill-2: instance 0, mill-1: instance 1) is asked until answered.
    REQUIRE(eventually(
        [&] {
            for (const char* tid : {"mill-1", "mill-2"})
                if (app.received_on(std::string("Register/Response/") + tid) == 0)
                    send("Register/Request", Json{{"@id", std::string("w-") + tid}, {"cli_uuid", tid}});
            return eventually(
                [&] { return app.received_on("Register/Response/mill-1") > 0 && app.received_on("Register/Response/mill-2") > 0; },
                1s);
        },
        60s));
    std::this_thread::sleep_for(500ms);  // a warm-up asked twice is answered before the count starts
    const std::uint64_t warm[2] = {agents[0]->stats().registrations, agents[1]->stats().registrations};

    const int n = 8;
    for (int i = 0; i < n; ++i) {
        const std::string t = "t" + std::to_string(i), a = "app" + std::to_string(i);
        send("Register/Request", Json{{"@id", "r" + t}, {"cli_uuid", t}});
        send("Discovery/Request/" + a, Json{{"@id", "d" + a}, {"guid", a}});
    }
    CHECK(eventually(
        [&] {
            for (int i = 0; i < n; ++i)
                if (app.received_on("Register/Response/t" + std::to_string(i)) == 0 ||
                    app.received_on("Discovery/Response/app" + std::to_string(i)) == 0)
                    return false;
            return true;
        },
        20s));
    std::this_thread::sleep_for(1s);  // room for a second answer to show up
    for (int i = 0; i < n; ++i) {
        INFO(i);
        CHECK(app.received_on("Register/Response/t" + std::to_string(i)) == 1);
        CHECK(app.received_on("Discovery/Response/app" + std::to_string(i)) == 1);
    }
    for (unsigned k = 0; k < 2; ++k) {
        INFO("instance " << k);
        CHECK(agents[k]->stats().registrations - warm[k] == n / 2);
        CHECK(agents[k]->stats().discoveries == n / 2);
    }
    for (auto& agent : agents) agent->stop();
}

// The agent's default, shared subscriptions, on ejabberd: mod_mqtt answers
// the SUBSCRIBE to $share/... by ending the connection (MQTT 5: DISCONNECT
// 0x9E first). Nobody is registered either way; what the agent's transport
// (paho) sees differs. At 3.1.1 the socket closes: connection lost, and it
// connects and subscribes again, over and over. At MQTT 5 paho takes the
// broker's DISCONNECT for the end of the connection without calling the
// connection-lost callback, the only one the transport listens to: the link
// stays "connected", deaf, with no reconnection.
TEST_CASE("ejabberd cluster: an agent with the default share_group is dropped at its SUBSCRIBE and registers nobody") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;

    AdapterConfig config = adapter_config(ejabberd, 0, "ej-shared-adapter");
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());

    std::uint64_t connects[2] = {0, 0};
    std::uint64_t failures[2] = {0, 0};
    for (int level : {5, 4}) {
        INFO("agent on MQTT " << level);
        AgentConfig agent_settings = agent_config(ejabberd, 2, "ej-shared-agent-" + std::to_string(level));
        agent_settings.mqtt_version = level;
        REQUIRE(agent_settings.share_group == "nclink-agent");
        Agent agent(agent_settings, probe_logger());
        REQUIRE(agent.start());
        REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));
        // Until it has connected again: at 3.1.1 ejabberd closes the
        // connection, at MQTT 5 it sends DISCONNECT 0x9E first, which the
        // paho transport takes for a lost connection too (before, it stayed
        // on its first connection, deaf). At once on an idle box; a loaded
        // one may delay the reconnection's back-off.
        eventually([&] { return agent.stats().transport.connects > 1; }, 30s);
        CHECK_FALSE(adapter.stats().registered);
        CHECK(agent.stats().registrations == 0);
        const std::size_t k = level == 5 ? 0 : 1;
        connects[k] = agent.stats().transport.connects;
        failures[k] = agent.stats().transport.connect_failures;
        agent.stop();
    }
    INFO("MQTT 5: " << connects[0] << " connects, " << failures[0] << " failures; 3.1.1: " << connects[1] << " connects, "
                    << failures[1] << " failures");
    CHECK(connects[0] > 1);
    CHECK(connects[1] > 1);
    std::printf(
        "ejabberd: an agent with share_group \"nclink-agent\" registered nobody; dropped at its SUBSCRIBE, it connected %llu "
        "time(s) on MQTT 5 (%llu failed attempts) and %llu times on MQTT 3.1.1 (%llu failed attempts)\n",
        static_cast<unsigned long long>(connects[0]), static_cast<unsigned long long>(failures[0]),
        static_cast<unsigned long long>(connects[1]), static_cast<unsigned long long>(failures[1]));

    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}
