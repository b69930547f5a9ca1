// Programs with a failover list (the broker section's "failover",
// MqttOptions::failover_urls) on two real mosquittos: an adapter
// (libmosquitto) whose first broker is not running, and an adapter and an
// application Client (paho) whose broker is killed under them; they meet on
// the second broker and Query (8.2.19/8.2.20) keeps being answered.
#include <nclink/adapter.hpp>
#include <nclink/adapter_metrics.hpp>
#include <nclink/client.hpp>

#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver
#include "support/mosquitto_broker.hpp"
#include "support/patient_query.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

Logger test_logger() { return std::getenv("NCLINK_TEST_LOG") ? Logger(stderr_sink(), LogLevel::debug) : Logger{}; }

AdapterConfig adapter_config(const std::string& url, std::vector<std::string> failover, const std::string& dir) {
    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = dir;
    config.broker_url = url;
    config.failover_urls = std::move(failover);
    config.client_id = "failover-adapter";
    config.register_timeout = 200ms;
    return config;
}

std::unique_ptr<Client> client_on(const std::string& url, std::vector<std::string> failover) {
    MqttOptions mqtt;
    mqtt.broker_url = url;
    mqtt.failover_urls = std::move(failover);
    mqtt.reconnect_min = 50ms;
    mqtt.reconnect_max = 500ms;
    ClientOptions o;
    o.ex_cid = "failover-app";
    o.default_timeout = 300ms;  // the registration nobody answers (no agent here)
    o.logger = test_logger();
    auto made = Client::create(std::move(mqtt), o);
    REQUIRE(made);
    auto client = std::move(made).value();
    auto outcome = client->connect(20s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);
    return client;
}

// The adapter's answer to a Query of two items, asked until it comes.
void query_answered(Client& client) {
    const auto answer = patient_query(client);
    REQUIRE(answer.size() == 2);
    REQUIRE(answer[0].values);
    CHECK(*answer[0].values == Json::array({12.5}));
}

}  // namespace

TEST_CASE("failover: an adapter whose first broker is not running serves on the second, a Client there gets its answers") {
    MosquittoOptions down;
    down.start = false;  // a port nothing listens on
    MosquittoBroker first(down);
    MosquittoBroker second;
    const std::string dir = scratch_dir("failover-adapter");
    auto driver = std::make_shared<FakeDriver>();
    Adapter adapter(adapter_config(first.url(), {"127.0.0.1:" + std::to_string(second.port())}, dir), driver, test_logger());
    REQUIRE(adapter.start());
    REQUIRE(eventually([&] { return adapter.state() == AdapterState::normal; }, 20s));

    auto client = client_on(second.url(), {});
    query_answered(*client);

    // Where the statistics show it: TransportStats, the stats JSON, /metrics.
    const TransportStats link = adapter.stats().transport;
    CHECK(link.failovers == 1);
    CHECK(link.broker == "tcp://127.0.0.1:" + std::to_string(second.port()));
    const Json json = to_json(adapter.stats());
    CHECK(json["transport"]["failovers"] == 1);
    CHECK(json["transport"]["broker"] == link.broker);
    const std::string metrics = prometheus_metrics(adapter);
    CHECK_THAT(metrics, Catch::Contains("nclink_adapter_mqtt_failovers_total{dev=\"test-dev\"} 1"));
    CHECK_THAT(metrics, Catch::Contains("nclink_adapter_mqtt_broker{dev=\"test-dev\",broker=\"" + link.broker + "\"} 1"));

    client->stop();
    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
}

TEST_CASE("failover: the broker of an adapter and a Client is killed, both move to the second and Query is answered there") {
    MosquittoBroker first;
    MosquittoBroker second;
    const std::string dir = scratch_dir("failover-both");
    auto driver = std::make_shared<FakeDriver>();
    AdapterConfig config = adapter_config(first.url(), {second.url()}, dir);
    Adapter adapter(config, driver, test_logger());
    REQUIRE(adapter.start());
    REQUIRE(eventually([&] { return adapter.state() == AdapterState::normal; }, 20s));
    auto client = client_on(first.url(), {second.url()});
    query_answered(*client);
    CHECK(client->stats().transport.broker == first.url());

    first.crash();  // kill -9
    REQUIRE(eventually([&] { return client->stats().transport.broker == second.url() && client->wait_connected(10ms); }, 30s));
    query_answered(*client);

    const TransportStats adapter_link = adapter.stats().transport;
    CHECK(adapter_link.broker == second.url());
    CHECK(adapter_link.failovers == 1);
    const TransportStats client_link = client->stats().transport;
    CHECK(client_link.failovers == 1);
    CHECK(client_link.connects == 2);

    client->stop();
    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
}
