// One agent on a RabbitMQ cluster, with the settings docs/scaling.md gives
// for it there: MQTT 3.1.1 and plain subscriptions (share_group ""; RabbitMQ
// takes $share/... for a topic name). Agent on node 3, adapter on node 1,
// application on node 2: registration (8.2.1) and Discovery (8.2.3) cross
// the cluster.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("RabbitMQ cluster: one agent with plain subscriptions registers an adapter and answers Discovery across nodes") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;

    AgentConfig agent_config;
    agent_config.broker_url = rabbit.url(2);
    agent_config.client_id = "cluster-agent";
    agent_config.mqtt_version = 4;
    agent_config.share_group = "";
    Agent agent(agent_config, probe_logger());
    REQUIRE(agent.start());
    REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));

    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = scratch_dir("cluster-agent-adapter");
    config.broker_url = rabbit.url(0);
    config.client_id = "cluster-adapter";
    config.mqtt_version = 0;  // "auto"
    config.register_timeout = 300ms;
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());
    // The agent's SUBSCRIBEs may still be on their way: the adapter asks again until accepted.
    CHECK(eventually([&] { return adapter.stats().registered; }, 60s));

    MqttOptions mqtt;
    mqtt.broker_url = rabbit.url(1);
    mqtt.mqtt_version = 4;
    ClientOptions o;
    o.ex_cid = "cluster-app";
    o.default_timeout = 3s;
    auto made = Client::create(std::move(mqtt), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::accepted);

    std::vector<DeviceListEntry> listed;
    CHECK(eventually(
        [&] {
            auto found = client.discover();
            if (!found) return false;
            listed = *found;
            for (const auto& entry : listed)
                if (entry.guid == "test-dev" && entry.status == "online") return true;
            return false;
        },
        30s));

    client.stop();
    adapter.stop();
    agent.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}
