// nclink on a RabbitMQ cluster: an adapter (libmosquitto transport,
// mqtt_version "auto") connected to node 1 and an application's Client (paho,
// MQTT 3.1.1) connected to node 2; a Query (8.2.19/8.2.20) goes from one
// node to the other and back.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>

#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver
#include "support/patient_query.hpp"

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("RabbitMQ cluster: an adapter on node 1 answers a Query from a client on node 2, MQTT auto falling back to 3.1.1") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;

    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = scratch_dir("cluster-adapter");
    config.broker_url = rabbit.url(0);
    config.client_id = "cluster-adapter";
    config.mqtt_version = 0;  // "auto": RabbitMQ 3.10 closes the MQTT 5 CONNECT, 3.1.1 follows
    config.register_timeout = 200ms;
    auto driver = std::make_shared<FakeDriver>();
    Adapter adapter(config, driver, probe_logger());
    REQUIRE(adapter.start());
    REQUIRE(eventually([&] { return adapter.state() == AdapterState::normal; }, 60s));
    // The MQTT 5 attempt that came first failed; 3.1.1 connected.
    CHECK(adapter.stats().transport.connect_failures >= 1);
    CHECK(adapter.stats().transport.connects == 1);

    // Without "auto" an adapter asking for MQTT 5 never gets in.
    {
        AdapterConfig five = config;
        five.client_id = "cluster-adapter-5";
        five.device_id.clear();
        five.mqtt_version = 5;
        five.persistence_dir = scratch_dir("cluster-adapter-5");
        Adapter refused(five, std::make_shared<FakeDriver>(), probe_logger());
        REQUIRE(refused.start());
        CHECK(eventually([&] { return refused.stats().transport.connect_failures >= 3; }, 30s));
        CHECK(refused.stats().transport.connects == 0);
        refused.stop();
        std::error_code ignored;
        std::filesystem::remove_all(five.persistence_dir, ignored);
    }

    MqttOptions mqtt;
    mqtt.broker_url = rabbit.url(1);
    mqtt.mqtt_version = 4;
    ClientOptions o;
    o.ex_cid = "cluster-app";
    o.default_timeout = 300ms;  // the registration nobody answers (no agent here)
    auto made = Client::create(std::move(mqtt), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);

    // The adapter's SUBSCRIBE may still be on its way through the cluster:
    // asked again until answered.
    const auto answer = patient_query(client);
    REQUIRE(answer.size() == 2);
    REQUIRE(answer[0].values);
    CHECK(*answer[0].values == Json::array({12.5}));
    REQUIRE(answer[1].values);
    CHECK(*answer[1].values == Json::array({"running"}));

    client.stop();
    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}
