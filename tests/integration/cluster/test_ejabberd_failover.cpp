// An ejabberd node killed under nclink programs that list the cluster's
// nodes as their failover list (docs/configuration.md, "Failover to other
// brokers"): an adapter (libmosquitto, mqtt_version "auto": MQTT 5 here) and
// an application's Client (paho, MQTT 5) on node 1, an agent (MQTT 5, plain
// subscriptions) on node 3, all logged in. Node 1 is killed -9: the adapter
// and the Client move to another node and Query (8.2.19/8.2.20) is answered
// there while node 1 is dead, unlike on RabbitMQ 3.10
// (test_failover_on_cluster.cpp). Each CHECK states what happened, so an
// ejabberd that behaves differently fails the test and docs/scaling.md gets
// corrected.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver

#include <cstdio>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("ejabberd cluster: node 1 killed under an adapter and a Client with the nodes as failover list") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;

    AgentConfig agent_config;
    agent_config.broker_url = ejabberd.url(2);
    agent_config.failover_urls = {ejabberd.url(0), ejabberd.url(1)};
    agent_config.client_id = "ej-failover-agent";
    agent_config.username = EjabberdCluster::username();
    agent_config.password = EjabberdCluster::password();
    agent_config.mqtt_version = 5;
    agent_config.share_group = "";
    Agent agent(agent_config, probe_logger());
    REQUIRE(agent.start());
    REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));

    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = scratch_dir("ej-failover-adapter");
    config.broker_url = ejabberd.url(0);
    config.failover_urls = {ejabberd.url(1), ejabberd.url(2)};
    config.client_id = "ej-failover-adapter";
    config.username = EjabberdCluster::username();
    config.password = EjabberdCluster::password();
    config.mqtt_version = 0;
    config.register_timeout = 300ms;
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());
    CHECK(eventually([&] { return adapter.stats().registered; }, 60s));

    MqttOptions mqtt;
    mqtt.broker_url = ejabberd.url(0);
    mqtt.failover_urls = {ejabberd.url(1), ejabberd.url(2)};
    mqtt.mqtt_version = 5;
    mqtt.username = EjabberdCluster::username();
    mqtt.password = EjabberdCluster::password();
    ClientOptions o;
    o.ex_cid = "ej-failover-app";
    o.default_timeout = 3s;
    o.logger = probe_logger();
    auto made = Client::create(std::move(mqtt), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::accepted);
    REQUIRE(query_answered(client, 60s));
    CHECK(client.stats().transport.broker == ejabberd.url(0));

    ejabberd.kill_node(0);
    const auto killed = std::chrono::steady_clock::now();
    // Both fail over to another node, which keeps them ...
    CHECK(eventually(
        [&] { return adapter.stats().transport.broker != ejabberd.url(0) && adapter.stats().transport.connects >= 2; }, 30s));
    CHECK(eventually([&] { return client.stats().transport.broker != ejabberd.url(0) && client.stats().transport.connects >= 2; },
                     30s));
    CHECK(adapter.stats().transport.failovers >= 1);
    CHECK(client.stats().transport.failovers >= 1);
    // ... and a Query is answered there while node 1 is dead.
    const bool answered_while_dead = query_answered(client, 30s);
    CHECK(answered_while_dead);
    const auto answered = std::chrono::steady_clock::now();
    const TransportStats adapter_before = adapter.stats().transport;
    std::this_thread::sleep_for(5s);
    const TransportStats adapter_after = adapter.stats().transport;
    CHECK(adapter_after.connects == adapter_before.connects);  // it stays where it landed
    CHECK(agent.stats().transport.failovers == 0);

    // "node N" for a URL of the cluster (1-based, as above).
    const auto node_of = [&](const std::string& url) {
        for (int i = 0; i < ejabberd.size(); ++i)
            if (ejabberd.url(i) == url) return "node " + std::to_string(i + 1);
        return url;
    };
    using std::chrono::duration_cast;
    using std::chrono::milliseconds;
    std::printf(
        "ejabberd failover: node 1 killed; a Query answered while it was dead: %s, %lld ms after the kill; adapter on %s "
        "(%llu connections, %llu failovers, %llu sessions lost), Client on %s (%llu failovers); the adapter reconnected %llu "
        "times in the 5 s after\n",
        answered_while_dead ? "yes" : "no", static_cast<long long>(duration_cast<milliseconds>(answered - killed).count()),
        node_of(adapter_after.broker).c_str(), static_cast<unsigned long long>(adapter_after.connects),
        static_cast<unsigned long long>(adapter_after.failovers), static_cast<unsigned long long>(adapter_after.sessions_lost),
        node_of(client.stats().transport.broker).c_str(), static_cast<unsigned long long>(client.stats().transport.failovers),
        static_cast<unsigned long long>(adapter_after.connects - adapter_before.connects));

    client.stop();
    adapter.stop();
    agent.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}
