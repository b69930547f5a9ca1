// A cluster node killed under nclink programs that list the cluster's nodes
// as their failover list (docs/configuration.md, "Failover to other
// brokers"), on RabbitMQ and on ejabberd: an adapter (libmosquitto,
// mqtt_version "auto") and an application's Client (paho) on node 1, an
// agent (plain subscriptions) on node 3, logged in where the broker wants it.
// Node 1 is killed -9 and the adapter and the Client move to another node.
// What follows is where the brokers differ (WhileDead): RabbitMQ 3.10 drops
// them there right after each CONNACK, and on node 3 too (the client ids
// lived on the dead node, docs/scaling.md), so they go round the list and
// Query (8.2.19/8.2.20) is answered only once node 1 is back; ejabberd keeps
// them where they landed and answers the Query there while node 1 is dead.
// Each CHECK states what the broker did, so a broker that behaves
// differently fails the test and docs/scaling.md gets corrected.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_configs.hpp"
#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // FakeDriver

#include <cstdio>
#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

// What the cluster does with the programs that left node 1 while it is dead.
enum class WhileDead {
    // RabbitMQ 3.10: accepted on node 2 and node 3 and dropped within
    // milliseconds, until node 1 is back.
    dropped_everywhere,
    // ejabberd 23.01: kept on the node they moved to, and served there.
    served_elsewhere,
};

// `mqtt_version`: the agent's and the Client's ("auto" on RabbitMQ, which
// closes an MQTT 5 CONNECT; 5 on ejabberd, which takes it). The adapter is
// on "auto" on both.
template <class Cluster>
void failover_through_node_loss(Cluster& cluster, const Login& login, int mqtt_version, WhileDead while_dead) {
    AgentConfig agent_settings = agent_config(cluster, 2, "cluster-failover-agent", login, mqtt_version);
    agent_settings.failover_urls = other_nodes(cluster, 2);
    agent_settings.share_group = "";
    Agent agent(agent_settings, probe_logger());
    REQUIRE(agent.start());
    REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));
    CHECK(agent.stats().transport.broker == cluster.url(2));

    AdapterConfig config = adapter_config(cluster, 0, "cluster-failover-adapter", login);
    config.failover_urls = other_nodes(cluster, 0);
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());
    CHECK(eventually([&] { return adapter.stats().registered; }, 60s));

    MqttOptions mqtt = client_mqtt(cluster, 0, login, mqtt_version);
    mqtt.failover_urls = other_nodes(cluster, 0);
    ClientOptions o;
    o.ex_cid = "cluster-failover-app";
    o.default_timeout = 3s;
    o.logger = probe_logger();
    auto made = Client::create(std::move(mqtt), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::accepted);
    REQUIRE(query_answered(client, 60s));
    CHECK(client.stats().transport.broker == cluster.url(0));

    cluster.kill_node(0);
    const auto killed = std::chrono::steady_clock::now();
    // Both fail over to another node ...
    CHECK(eventually(
        [&] { return adapter.stats().transport.broker != cluster.url(0) && adapter.stats().transport.connects >= 2; }, 30s));
    CHECK(eventually([&] { return client.stats().transport.broker != cluster.url(0) && client.stats().transport.connects >= 2; },
                     30s));
    CHECK(adapter.stats().transport.failovers >= 1);
    CHECK(client.stats().transport.failovers >= 1);

    // "node N" for a URL of the cluster (1-based, as above).
    const auto node_of = [&](const std::string& url) {
        for (int i = 0; i < cluster.size(); ++i)
            if (cluster.url(i) == url) return "node " + std::to_string(i + 1);
        return url;
    };
    using std::chrono::duration_cast;
    using std::chrono::milliseconds;
    if (while_dead == WhileDead::dropped_everywhere) {
        // ... where RabbitMQ 3.10 accepts their CONNECT and drops the
        // connection within milliseconds, on node 2 and node 3 alike, while
        // node 1 is dead (the client ids lived there, docs/scaling.md). Each
        // drop counts as a failed attempt (src/transport/backoff.hpp) and,
        // since it came before the connection was stable, moves the program
        // on to the next node of its list
        // (src/transport/connection_lost.hpp): it goes round the list with a
        // growing back-off instead of staying on node 2.
        const TransportStats adapter_before = adapter.stats().transport;
        std::this_thread::sleep_for(10s);
        const TransportStats adapter_after = adapter.stats().transport;
        const std::uint64_t dropped = adapter_after.connects - adapter_before.connects;
        const std::uint64_t moved = adapter_after.failovers - adapter_before.failovers;
        CHECK(dropped <= 8);                  // not in a storm
        CHECK(adapter_after.failovers >= 2);  // node 2 dropped it: on to node 3 (before: 1, held by node 2)
        const bool answered_while_dead = query_answered(client, 5s);
        CHECK_FALSE(answered_while_dead);  // no node serves them while node 1 is dead

        cluster.start_node(0);
        const auto back = std::chrono::steady_clock::now();
        CHECK(query_answered(client, 90s));
        const auto answered = std::chrono::steady_clock::now();
        CHECK(agent.stats().transport.failovers == 0);
        std::printf(
            "failover on the cluster: node 1 killed; in the 10 s after the adapter left it: %llu connection(s), %llu "
            "failover(s), then on %s; a Query answered while node 1 was dead: %s; node 1 back %lld ms after the kill; a Query "
            "answered %lld ms after that; adapter on %s (%llu failovers), Client on %s (%llu failovers)\n",
            static_cast<unsigned long long>(dropped), static_cast<unsigned long long>(moved), node_of(adapter_after.broker).c_str(),
            answered_while_dead ? "yes" : "no", static_cast<long long>(duration_cast<milliseconds>(back - killed).count()),
            static_cast<long long>(duration_cast<milliseconds>(answered - back).count()),
            node_of(adapter.stats().transport.broker).c_str(), static_cast<unsigned long long>(adapter.stats().transport.failovers),
            node_of(client.stats().transport.broker).c_str(), static_cast<unsigned long long>(client.stats().transport.failovers));
    } else {
        // ... which keeps them, and a Query is answered there while node 1
        // is dead.
        const bool answered_while_dead = query_answered(client, 30s);
        CHECK(answered_while_dead);
        const auto answered = std::chrono::steady_clock::now();
        const TransportStats adapter_before = adapter.stats().transport;
        std::this_thread::sleep_for(5s);
        const TransportStats adapter_after = adapter.stats().transport;
        CHECK(adapter_after.connects == adapter_before.connects);  // it stays where it landed
        CHECK(agent.stats().transport.failovers == 0);
        std::printf(
            "ejabberd failover: node 1 killed; a Query answered while it was dead: %s, %lld ms after the kill; adapter on %s "
            "(%llu connections, %llu failovers, %llu sessions lost), Client on %s (%llu failovers); the adapter reconnected %llu "
            "times in the 5 s after\n",
            answered_while_dead ? "yes" : "no", static_cast<long long>(duration_cast<milliseconds>(answered - killed).count()),
            node_of(adapter_after.broker).c_str(), static_cast<unsigned long long>(adapter_after.connects),
            static_cast<unsigned long long>(adapter_after.failovers), static_cast<unsigned long long>(adapter_after.sessions_lost),
            node_of(client.stats().transport.broker).c_str(), static_cast<unsigned long long>(client.stats().transport.failovers),
            static_cast<unsigned long long>(adapter_after.connects - adapter_before.connects));
    }

    client.stop();
    adapter.stop();
    agent.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}

}  // namespace

TEST_CASE("RabbitMQ cluster: node 1 killed under an adapter and a Client with the nodes as failover list") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;
    failover_through_node_loss(rabbit, Login{}, 0, WhileDead::dropped_everywhere);
}

TEST_CASE("ejabberd cluster: node 1 killed under an adapter and a Client with the nodes as failover list") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;
    failover_through_node_loss(ejabberd, ejabberd_login(), 5, WhileDead::served_elsewhere);
}
