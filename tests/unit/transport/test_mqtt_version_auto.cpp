// mqtt_version 0 ("auto") of the libmosquitto transport against a broker
// that, as RabbitMQ 3.10 does, closes the connection of an MQTT 5 CONNECT
// without a CONNACK and accepts MQTT 3.1.1: a stand-in on a loopback port
// that records the protocol level (MQTT 3.1.2.2 / 5.0 3.1.2.2) of every
// CONNECT it reads (support/mqtt5_refusing_broker.hpp; the paho transport's
// tests, tests/unit/paho, use it too).
#include <nclink/mqtt_transport.hpp>

#include "support/mosquitto_broker.hpp"  // free_loopback_port()
#include "support/mqtt5_refusing_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <mutex>
#include <string>
#include <string_view>
#include <vector>

using namespace nclink;
using nclink::test::eventually;
using namespace std::chrono_literals;

namespace {

MqttOptions options_for(const std::string& url, int version) {
    MqttOptions o;
    o.broker_url = url;
    o.client_id = "auto-version";
    o.mqtt_version = version;
    o.reconnect_min = 20ms;
    o.reconnect_max = 100ms;
    return o;
}

}  // namespace

TEST_CASE("mqtt_version auto falls back to MQTT 3.1.1 when the broker closes a 5 CONNECT, and keeps it") {
    nclink::test::Mqtt5RefusingBroker broker;
    auto made = make_mqtt_transport(options_for(broker.url(), 0));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5, 4});

    // A reconnection speaks the level that was accepted, at once.
    broker.drop_clients();
    REQUIRE(eventually([&] { return broker.levels().size() == 3 && transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5, 4, 4});
    transport.stop(0ms);
}

TEST_CASE("mqtt_version 5 stays 5 with a broker that refuses it") {
    nclink::test::Mqtt5RefusingBroker broker;
    auto made = make_mqtt_transport(options_for(broker.url(), 5));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return broker.levels().size() >= 3; }, 10s));
    CHECK(transport.state() != LinkState::connected);
    for (int level : broker.levels()) CHECK(level == 5);
    transport.stop(0ms);
}

TEST_CASE("mqtt_version auto with a failover list: the broker failed over to is asked for 5 first, then 3.1.1") {
    nclink::test::Mqtt5RefusingBroker first;
    first.accept_mqtt5(true);
    nclink::test::Mqtt5RefusingBroker second;
    MqttOptions o = options_for(first.url(), 0);
    o.failover_urls = {second.url()};
    auto made = make_mqtt_transport(o);
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

// The failover above read "connected to the second broker" once, under
// qemu, before the second broker had seen a CONNECT: the link still read
// connected while the statistics already named the broker tried next.
TEST_CASE("a lost link reads disconnected before its statistics name the broker of the failover list tried next") {
    nclink::test::Mqtt5RefusingBroker first;
    nclink::test::Mqtt5RefusingBroker second;
    MqttOptions o = options_for(first.url(), 4);
    o.failover_urls = {second.url()};
    auto made = make_mqtt_transport(o);
    REQUIRE(made);
    auto& transport = **made;
    std::mutex mutex;
    std::vector<std::string> disconnected_on;  // stats().broker as each disconnected state is announced
    transport.set_state_handler([&](LinkState state, std::string_view) {
        if (state != LinkState::disconnected) return;
        const std::string broker = transport.stats().broker;
        std::lock_guard<std::mutex> lock(mutex);
        disconnected_on.push_back(broker);
    });
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    first.drop_clients();  // lost before it was stable: the next attempt goes to the second broker
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected && transport.stats().broker == second.url(); }, 10s));
    CHECK(second.levels() == std::vector<int>{4});
    CHECK(transport.stats().failovers == 1);
    {
        std::lock_guard<std::mutex> lock(mutex);
        CHECK(disconnected_on == std::vector<std::string>{first.url()});
    }
    transport.stop(0ms);
}

TEST_CASE("mqtt_version auto: a broker that is down is not taken for one that refuses 5") {
    const int port = nclink::test::free_loopback_port();
    auto made = make_mqtt_transport(options_for("tcp://127.0.0.1:" + std::to_string(port), 0));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.stats().connect_failures >= 3; }, 10s));
    nclink::test::Mqtt5RefusingBroker broker(0, port);  // up now, and it speaks 5
    broker.accept_mqtt5(true);
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5});
    transport.stop(0ms);
}
