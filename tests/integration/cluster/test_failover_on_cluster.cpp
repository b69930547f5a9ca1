// A RabbitMQ node killed under nclink programs that list the cluster's nodes
// as their failover list (docs/configuration.md, "Failover to other
// brokers"): an adapter (libmosquitto) and an application's Client (paho),
// both with mqtt_version "auto" (RabbitMQ refuses MQTT 5: 3.1.1 follows), on
// node 1; an agent ("auto", plain subscriptions) on node 3. Node 1 is killed
// -9: the adapter and the Client move to node 2 at once, but RabbitMQ 3.10
// drops them there right after each CONNACK, and on node 3 too (the client
// ids lived on the dead node, docs/scaling.md), so they go round the list;
// once node 1 is back, Query (8.2.19/8.2.20) is answered wherever they are.
// Each CHECK states what the broker did, so a RabbitMQ that behaves
// differently fails the test and the documentation gets corrected.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver

#include <cstdio>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("RabbitMQ cluster: node 1 killed under an adapter and a Client with the nodes as failover list") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;

    AgentConfig agent_config;
    agent_config.broker_url = rabbit.url(2);
    agent_config.failover_urls = {rabbit.url(0), rabbit.url(1)};
    agent_config.client_id = "cluster-agent";
    agent_config.mqtt_version = 0;  // "auto": RabbitMQ closes the MQTT 5 CONNECT, 3.1.1 follows
    agent_config.share_group = "";
    Agent agent(agent_config, probe_logger());
    REQUIRE(agent.start());
    REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));
    CHECK(agent.stats().transport.broker == rabbit.url(2));

    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = scratch_dir("cluster-failover-adapter");
    config.broker_url = rabbit.url(0);
    config.failover_urls = {rabbit.url(1), rabbit.url(2)};
    config.client_id = "cluster-failover-adapter";
    config.mqtt_version = 0;
    config.register_timeout = 300ms;
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());
    CHECK(eventually([&] { return adapter.stats().registered; }, 60s));

    MqttOptions mqtt;
    mqtt.broker_url = rabbit.url(0);
    mqtt.failover_urls = {rabbit.url(1), rabbit.url(2)};
    mqtt.mqtt_version = 0;
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
    CHECK(client.stats().transport.broker == rabbit.url(0));

    rabbit.kill_node(0);
    const auto killed = std::chrono::steady_clock::now();
    // Both fail over to another node ...
    CHECK(eventually([&] { return adapter.stats().transport.broker != rabbit.url(0) && adapter.stats().transport.connects >= 2; },
                     30s));
    CHECK(eventually([&] { return client.stats().transport.broker != rabbit.url(0) && client.stats().transport.connects >= 2; },
                     30s));
    CHECK(adapter.stats().transport.failovers >= 1);
    CHECK(client.stats().transport.failovers >= 1);
    // ... where RabbitMQ 3.10 accepts their CONNECT and drops the
    // connection within milliseconds, on node 2 and node 3 alike, while node
    // 1 is dead (the client ids lived there, docs/scaling.md). Each drop
    // counts as a failed attempt (src/transport/backoff.hpp) and, since it
    // came before the connection was stable, moves the program on to the
    // next node of its list (src/transport/connection_lost.hpp): it goes
    // round the list with a growing back-off instead of staying on node 2.
    const TransportStats adapter_before = adapter.stats().transport;
    std::this_thread::sleep_for(10s);
    const TransportStats adapter_after = adapter.stats().transport;
    const std::uint64_t dropped = adapter_after.connects - adapter_before.connects;
    const std::uint64_t moved = adapter_after.failovers - adapter_before.failovers;
    CHECK(dropped <= 8);                  // not in a storm
    CHECK(adapter_after.failovers >= 2);  // node 2 dropped it: on to node 3 (before: 1, held by node 2)
    const bool answered_while_dead = query_answered(client, 5s);
    CHECK_FALSE(answered_while_dead);  // no node serves them while node 1 is dead

    rabbit.start_node(0);
    const auto back = std::chrono::steady_clock::now();
    CHECK(query_answered(client, 90s));
    const auto answered = std::chrono::steady_clock::now();
    CHECK(agent.stats().transport.failovers == 0);
    // "node N" for a URL of the cluster (1-based, as above).
    const auto node_of = [&](const std::string& url) {
        for (int i = 0; i < rabbit.size(); ++i)
            if (rabbit.url(i) == url) return "node " + std::to_string(i + 1);
        return url;
    };
    using std::chrono::duration_cast;
    using std::chrono::milliseconds;
    std::printf(
        "failover on the cluster: node 1 killed; in the 10 s after the adapter left it: %llu connection(s), %llu failover(s), "
        "then on %s; a Query answered while node 1 was dead: %s; node 1 back %lld ms after the kill; a Query answered %lld ms "
        "after that; adapter on %s (%llu failovers), Client on %s (%llu failovers)\n",
        static_cast<unsigned long long>(dropped), static_cast<unsigned long long>(moved), node_of(adapter_after.broker).c_str(),
        answered_while_dead ? "yes" : "no", static_cast<long long>(duration_cast<milliseconds>(back - killed).count()),
        static_cast<long long>(duration_cast<milliseconds>(answered - back).count()),
        node_of(adapter.stats().transport.broker).c_str(), static_cast<unsigned long long>(adapter.stats().transport.failovers),
        node_of(client.stats().transport.broker).c_str(), static_cast<unsigned long long>(client.stats().transport.failovers));

    client.stop();
    adapter.stop();
    agent.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}
