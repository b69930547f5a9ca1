// Agents on a 3-node cluster, RabbitMQ or ejabberd, with the settings
// docs/scaling.md gives for them there: plain subscriptions (share_group "":
// RabbitMQ takes $share/... for a topic name, ejabberd's mod_mqtt closes the
// connection at a SUBSCRIBE to it), one instance or several splitting the
// requests by terminal id; MQTT 3.1.1 and no login on RabbitMQ, MQTT 5 and a
// login on ejabberd. Registration (8.2.1) and Discovery (8.2.3) cross the
// cluster. Each behaviour is written once, over the cluster type, and run by
// one TEST_CASE per broker.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_configs.hpp"
#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // FakeDriver

#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

// Agent on node 3, adapter on node 1, application on node 2. `mqtt_version`:
// the agent's and the application's. `share_group`: "" as docs/scaling.md
// gives it, or the default, which the agent checks at start and drops for
// plain subscriptions on a broker without $share (docs/agent.md).
template <class Cluster>
void one_agent_across_nodes(Cluster& cluster, const Login& login, int mqtt_version, const std::string& share_group = "") {
    AgentConfig agent_settings = agent_config(cluster, 2, "cluster-agent", login, mqtt_version);
    agent_settings.share_group = share_group;
    Agent agent(agent_settings, probe_logger());
    REQUIRE(agent.start());
    CHECK(agent.share_group_in_use().empty());
    REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));

    AdapterConfig config = adapter_config(cluster, 0, "cluster-agent-adapter", login);
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());
    // The agent's SUBSCRIBEs may still be on their way: the adapter asks again until accepted.
    CHECK(eventually([&] { return adapter.stats().registered; }, 60s));

    ClientOptions o;
    o.ex_cid = "cluster-app";
    o.default_timeout = 3s;
    auto made = Client::create(client_mqtt(cluster, 1, login, mqtt_version), o);
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
// "instances" 2 (docs/agent.md, "Without $share"). Agents on nodes 2 and 3,
// the application on node 1: every request is answered once, by the instance
// its terminal id hashes to (FNV-1a 32 mod 2: t0..t7 and app0..app7 fall
// half to each). `mqtt_version`: the agents'.
template <class Cluster>
void two_agents_split_by_terminal(Cluster& cluster, const Login& login, int mqtt_version) {
    std::unique_ptr<Agent> agents[2];
    for (unsigned k = 0; k < 2; ++k) {
        AgentConfig c = agent_config(cluster, 1 + static_cast<int>(k), "cluster-agent-" + std::to_string(k), login, mqtt_version);
        c.share_group = "";
        c.instances = 2;
        c.instance = k;
        agents[k] = std::make_unique<Agent>(c, probe_logger());
        REQUIRE(agents[k]->start());
        REQUIRE(eventually([&] { return agents[k]->stats().transport.connects >= 1; }, 30s));
    }
    Probe app(cluster.url(0), "cluster-split-app", true, 4, login.username, login.password);
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

}  // namespace

// MQTT 3.1.1 on RabbitMQ: 3.10 closes an MQTT 5 CONNECT (test_broker_behaviour.cpp).
// MQTT 5 on ejabberd: what docs/scaling.md gives it there.

TEST_CASE("RabbitMQ cluster: one agent with plain subscriptions registers an adapter and answers Discovery across nodes") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;
    one_agent_across_nodes(rabbit, Login{}, 4);
}

TEST_CASE("ejabberd cluster: one agent with plain subscriptions registers an adapter and answers Discovery across nodes") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;
    one_agent_across_nodes(ejabberd, ejabberd_login(), 5);
}

// RabbitMQ 3.10 takes $share/... for a topic name, ejabberd 23.01 ends the
// connection at the SUBSCRIBE: either way the agent's check finds no
// shared subscriptions and it answers through plain ones.
TEST_CASE("RabbitMQ cluster: one agent with the default share group finds no $share and answers across nodes") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;
    one_agent_across_nodes(rabbit, Login{}, 4, AgentConfig{}.share_group);
}

TEST_CASE("ejabberd cluster: one agent with the default share group finds no $share and answers across nodes") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;
    one_agent_across_nodes(ejabberd, ejabberd_login(), 5, AgentConfig{}.share_group);
}

TEST_CASE("RabbitMQ cluster: two agents without $share split the requests by terminal and answer each once") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;
    two_agents_split_by_terminal(rabbit, Login{}, 4);
}

TEST_CASE("ejabberd cluster: two agents without $share split the requests by terminal and answer each once") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;
    two_agents_split_by_terminal(ejabberd, ejabberd_login(), 5);
}
