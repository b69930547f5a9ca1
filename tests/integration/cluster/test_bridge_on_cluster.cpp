// nclink-bridge on a 3-node cluster (RabbitMQ 3.10, ejabberd 23.01) with the
// settings docs/scaling.md gives: an adapter on node 1, one agent with plain
// subscriptions on node 3, the bridge on node 2 with MQTT "auto" and the
// other nodes as failover list. The bridge finds the machine (neither
// cluster hands retained online states across nodes, so the bridge must not
// depend on them), serves it as MTConnect (/probe, /current) with the value
// the adapter's driver reads, keeps serving while the adapter's node is
// killed, and serves the machine again once its node is back. While the
// node is dead the machine must show UNAVAILABLE: its last will died with
// the node, so only the bridge's own liveness check (a Query of one item
// after adapter_liveness_ms of silence; docs/bridge.md) can tell.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>

#include "bridge/bridge.hpp"
#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver

#include <httplib.h>

#include <cstdio>
#include <regex>
#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

// The text of `dataItemId` in a /current document ("" when absent).
std::string shown(const std::string& body, const std::string& data_item) {
    std::smatch m;
    if (!std::regex_search(body, m, std::regex("dataItemId=\"" + data_item + "\"[^>]*>([^<]*)<"))) return "";
    return m[1];
}

template <class Cluster>
void bridge_across_nodes(Cluster& cluster, const Login& login, const char* broker) {
    AgentConfig agent_settings;
    agent_settings.broker_url = cluster.url(2);
    agent_settings.client_id = "cl-bridge-agent";
    agent_settings.username = login.username;
    agent_settings.password = login.password;
    agent_settings.mqtt_version = 0;
    agent_settings.share_group = "";
    // What docs/scaling.md gives agents on a cluster: the adapter's will dies
    // with its node, so only the agent's question tells Discovery.
    agent_settings.adapter_liveness = 2000ms;
    agent_settings.request_timeout = 1000ms;
    Agent agent(agent_settings, probe_logger());
    REQUIRE(agent.start());

    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = scratch_dir("cl-bridge-adapter");
    config.broker_url = cluster.url(0);
    config.client_id = "cl-bridge-adapter";
    config.username = login.username;
    config.password = login.password;
    config.mqtt_version = 0;
    config.register_timeout = 300ms;
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());
    // The agent's SUBSCRIBEs may still be on their way: the adapter asks again until accepted.
    REQUIRE(eventually([&] { return adapter.stats().registered; }, 60s));

    bridge::BridgeConfig c;
    c.broker_url = cluster.url(1);
    c.failover_urls = {cluster.url(2), cluster.url(0)};
    c.username = login.username;
    c.password = login.password;
    c.mqtt_version = 0;
    c.http_port = 0;
    c.shdr_port = 0;
    c.poll_interval = 200ms;
    c.discovery_interval = 1s;
    c.heartbeat = 500ms;
    c.adapter_liveness = 2000ms;
    c.request_timeout = 1000ms;
    c.ex_cid = "cl-bridge";
    bridge::Bridge the_bridge(c, probe_logger());
    REQUIRE(the_bridge.start().ok());
    httplib::Client http("127.0.0.1", the_bridge.http_port());
    http.set_read_timeout(10, 0);
    const auto current = [&] {
        auto r = http.Get("/current");
        return r && r->status == 200 ? r->body : std::string();
    };

    // Found and served: the probe lists the machine, /current shows the
    // value its driver reads (FakeDriver: pos 12.5) and that it is available.
    CHECK(eventually(
        [&] {
            auto probe = http.Get("/probe");
            return probe && probe->status == 200 && probe->body.find("uuid=\"test-dev\"") != std::string::npos;
        },
        60s));
    std::string body;
    CHECK(eventually(
        [&] {
            body = current();
            const std::string pos = shown(body, "test-dev.pos");
            return !pos.empty() && pos != "UNAVAILABLE" && std::stod(pos) == 12.5 &&
                   body.find(">AVAILABLE</Availability>") != std::string::npos;
        },
        60s));
    INFO(body);

    // The adapter's node killed -9: the bridge, on another node, keeps
    // answering; the adapter comes back with its node and the bridge
    // follows it again (a Probe and a Query after its online state).
    cluster.kill_node(0);
    const auto killed = std::chrono::steady_clock::now();
    bool answered = true, unavailable = false;
    double unavailable_after_s = 0;
    for (int i = 0; i < 40 && !unavailable; ++i) {
        const std::string during = current();
        answered = answered && !during.empty();
        unavailable = during.find(">UNAVAILABLE</Availability>") != std::string::npos;
        if (unavailable) unavailable_after_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
        else std::this_thread::sleep_for(500ms);
    }
    CHECK(answered);
    CHECK(unavailable);
    const auto agent_says = [&] {
        for (const auto& t : agent.terminals())
            if (t.id == "test-dev") return t.status;
        return std::string();
    };
    CHECK(eventually([&] { return agent_says() == "offline"; }, 20s));
    const double agent_offline_after_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
    std::printf(
        "bridge on the %s cluster: the machine's node killed; the bridge showed it UNAVAILABLE after %.1f s "
        "(liveness 2 s + request timeout 1 s); the agent said offline after %.1f s at the latest\n",
        broker, unavailable_after_s, agent_offline_after_s);
    cluster.start_node(0);
    REQUIRE(eventually(
        [&] {
            const AdapterStats stats = adapter.stats();
            return stats.transport.connects >= 2 && stats.state == AdapterState::normal;
        },
        120s));
    // The bridge reaches the machine again (its polls and refresh are
    // requests at the adapter) and serves it as available, with its value.
    const std::uint64_t requests_back = adapter.stats().requests;
    CHECK(eventually([&] { return adapter.stats().requests > requests_back + 2; }, 60s));
    CHECK(eventually(
        [&] {
            const std::string after = current();
            return after.find(">AVAILABLE</Availability>") != std::string::npos && shown(after, "test-dev.pos") == "12.5";
        },
        60s));
    CHECK(eventually([&] { return agent_says() == "online"; }, 30s));

    the_bridge.stop();
    adapter.stop();
    agent.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}

}  // namespace

TEST_CASE("RabbitMQ cluster: the bridge on node 2 serves an adapter of node 1 through an agent on node 3") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;
    bridge_across_nodes(rabbit, Login{}, "RabbitMQ");
}

TEST_CASE("ejabberd cluster: the bridge on node 2 serves an adapter of node 1 through an agent on node 3") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;
    bridge_across_nodes(ejabberd, ejabberd_login(), "ejabberd");
}
