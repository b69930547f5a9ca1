// mqtt_version 0 ("auto") of the paho transport (the agent's and the
// application Client's) against a broker that, as RabbitMQ 3.10 does, closes
// the connection of an MQTT 5 CONNECT without a CONNACK and accepts MQTT
// 3.1.1: the stand-in of support/mqtt5_refusing_broker.hpp, which records the
// protocol level of every CONNECT (the libmosquitto transport's tests of the
// same behaviour: tests/unit/transport/test_mqtt_version_auto.cpp).
#include <nclink/paho_transport.hpp>

#include "support/mosquitto_broker.hpp"  // free_loopback_port()
#include "support/mqtt5_refusing_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <memory>
#include <vector>

using namespace nclink;
using nclink::test::eventually;
using nclink::test::Mqtt5RefusingBroker;
using namespace std::chrono_literals;

namespace {

MqttOptions options_for(const std::string& url, int version) {
    MqttOptions o;
    o.broker_url = url;
    o.client_id = "paho-auto-version";
    o.mqtt_version = version;
    o.reconnect_min = 20ms;
    o.reconnect_max = 100ms;
    o.tcp_nodelay = false;
    return o;
}

}  // namespace

TEST_CASE("mqtt_version auto falls back to MQTT 3.1.1 when the broker closes a 5 CONNECT, and keeps it") {
    Mqtt5RefusingBroker broker;
    auto made = make_paho_transport(options_for(broker.url(), 0));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5, 4});

    // A reconnection speaks the level that was accepted, at once.
    broker.drop_clients();
    REQUIRE(eventually([&] { return broker.levels().size() == 3 && transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5, 4, 4});
    CHECK(transport.stats().connects == 2);
    transport.stop(0ms);
}

TEST_CASE("mqtt_version auto speaks MQTT 5 to a broker that takes it") {
    Mqtt5RefusingBroker broker;
    broker.accept_mqtt5(true);
    auto made = make_paho_transport(options_for(broker.url(), 0));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5});
    transport.stop(0ms);
}

TEST_CASE("mqtt_version 5 stays 5 with a broker that refuses it, and 4 stays 4") {
    Mqtt5RefusingBroker broker;
    auto five = make_paho_transport(options_for(broker.url(), 5));
    REQUIRE(five);
    REQUIRE((*five)->start());
    REQUIRE(eventually([&] { return broker.levels().size() >= 3; }, 10s));
    CHECK((*five)->state() != LinkState::connected);
    (*five)->stop(0ms);
    for (int level : broker.levels()) CHECK(level == 5);

    Mqtt5RefusingBroker other;
    other.accept_mqtt5(true);
    auto four = make_paho_transport(options_for(other.url(), 4));
    REQUIRE(four);
    REQUIRE((*four)->start());
    REQUIRE(eventually([&] { return (*four)->state() == LinkState::connected; }, 10s));
    CHECK(other.levels() == std::vector<int>{4});
    (*four)->stop(0ms);
}

TEST_CASE("mqtt_version auto with a failover list: the broker failed over to is asked for 5 first, then 3.1.1") {
    Mqtt5RefusingBroker first;
    first.accept_mqtt5(true);
    Mqtt5RefusingBroker second;
    MqttOptions o = options_for(first.url(), 0);
    o.failover_urls = {second.url()};
    auto made = make_paho_transport(o);
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(first.levels() == std::vector<int>{5});

    // The first broker goes; the second refuses 5 as RabbitMQ does.
    first.accept_mqtt5(false);
    first.drop_clients();
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected && transport.stats().broker == second.url(); }, 10s));
    CHECK(second.levels() == std::vector<int>{5, 4});
    CHECK(transport.stats().failovers == 1);
    transport.stop(0ms);
}

TEST_CASE("mqtt_version auto: a broker that is down is not taken for one that refuses 5") {
    const int port = nclink::test::free_loopback_port();
    auto made = make_paho_transport(options_for("tcp://127.0.0.1:" + std::to_string(port), 0));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.stats().connect_failures >= 3; }, 10s));
    Mqtt5RefusingBroker broker(0, port);  // up now, and it speaks 5
    broker.accept_mqtt5(true);
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5});
    transport.stop(0ms);
}

TEST_CASE("mqtt_version auto after a 3.1.1 connection fails over to the next broker at 3.1.1") {
    // paho refuses to connect at 5 once it has connected at 3.1.1: asking
    // the next broker for 5 would fail before a byte is sent, for ever.
    auto first = std::make_unique<Mqtt5RefusingBroker>();
    Mqtt5RefusingBroker second;
    second.accept_mqtt5(true);
    MqttOptions o = options_for(first->url(), 0);
    o.failover_urls = {second.url()};
    auto made = make_paho_transport(o);
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(first->levels() == std::vector<int>{5, 4});

    first.reset();  // gone: its port refuses from now on
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected && transport.stats().broker == second.url(); }, 10s));
    CHECK(second.levels() == std::vector<int>{4});
    CHECK(transport.stats().failovers == 1);
    transport.stop(0ms);
}
