// What a 3-node RabbitMQ cluster (Debian's 3.10, rabbitmq_mqtt) does with the
// MQTT features nclink relies on, measured next to one mosquitto 2.0 with the
// same probes: the rows of the compatibility matrix in docs/scaling.md. Each
// CHECK states the broker's behaviour as measured, so a broker version that
// changes it fails here and the matrix gets updated.
#include "cluster_probe.hpp"

#include "support/mosquitto_broker.hpp"

#include <algorithm>
#include <cstdio>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

// A retained message published through `pub_url` to `topic`; a new
// subscriber through `sub_url` to `filter`: did the retained message reach it?
bool retained_reaches(const std::string& pub_url, const std::string& sub_url, const std::string& topic, const std::string& filter,
                      const std::string& tag) {
    const std::string payload = "retained-" + tag;
    {
        Probe pub(pub_url, tag + "-pub");
        REQUIRE(pub.connected());
        REQUIRE(pub.transport->publish({topic, payload, 1, true}));
        REQUIRE(pub.transport->flush(5s));
    }
    Probe sub(sub_url, tag + "-sub");
    REQUIRE(sub.connected());
    REQUIRE(sub.subscribe_ready(filter, topic));
    // A retained message is sent right after the SUBACK, before the marker
    // (published after the SUBSCRIBE); a little grace all the same.
    std::this_thread::sleep_for(300ms);
    return sub.with_payload(payload) > 0;
}

// A client connects through `will_port` with a will and drops the TCP
// connection without DISCONNECT; does a subscriber on `sub_url` get the will?
bool will_reaches(int will_port, const std::string& sub_url, const std::string& tag) {
    const std::string topic = "nclink-test/" + tag + "/will";
    Probe sub(sub_url, tag + "-will-sub");
    REQUIRE(sub.connected());
    REQUIRE(sub.subscribe_ready(topic, topic));
    {
        RawPeer peer(will_port);
        Will will{topic, "gone-" + tag, 1};
        REQUIRE(peer.send(mqtt_connect(4, tag + "-will-client", &will)));
        const std::string connack = peer.receive(3s, 4);
        REQUIRE(connack.size() == 4);
        REQUIRE(connack[3] == 0);
    }  // closed without DISCONNECT: the broker must publish the will (3.1.2.5)
    return eventually([&] { return sub.with_payload("gone-" + tag) > 0; }, 5s);
}

// Two subscribers of `$share/g/<topic>`, through `url_a` and `url_b`; 20
// QoS 1 messages to <topic>: how many reach them, and how they are split.
struct SharedDelivery {
    std::size_t a = 0, b = 0;
    std::size_t total() const { return a + b; }
};
SharedDelivery shared_delivery(const std::string& url_a, const std::string& url_b, const std::string& tag) {
    const std::string topic = "nclink-test/" + tag + "/work";
    Probe a(url_a, tag + "-share-a"), b(url_b, tag + "-share-b");
    REQUIRE(a.connected());
    REQUIRE(b.connected());
    for (Probe* p : {&a, &b}) {
        REQUIRE(p->transport->subscribe({"$share/g/" + topic}, 1));
        REQUIRE(p->subscribe_ready("nclink-test/" + tag + "/ready/#", "nclink-test/" + tag + "/ready/" + (p == &a ? "a" : "b")));
    }
    Probe pub(url_a, tag + "-share-pub");
    REQUIRE(pub.connected());
    for (int i = 0; i < 20; ++i) REQUIRE(pub.transport->publish({topic, "job-" + std::to_string(i), 1, false}));
    REQUIRE(pub.transport->flush(5s));
    eventually([&] { return a.received_on(topic) + b.received_on(topic) >= 20; }, 3s);
    return {a.received_on(topic), b.received_on(topic)};
}

}  // namespace

TEST_CASE("RabbitMQ cluster: retained messages, last wills, $share and MQTT 5, next to mosquitto") {
    NCLINK_NEEDS_RABBITMQ();
    MosquittoBroker mosquitto;
    RabbitCluster rabbit;
    const std::string m = mosquitto.url();

    // Retained messages (MQTT 3.3.1.3): mosquitto delivers them to an exact
    // and a wildcard subscriber alike.
    CHECK(retained_reaches(m, m, "nclink-test/m/state/t1", "nclink-test/m/state/t1", "m-exact"));
    CHECK(retained_reaches(m, m, "nclink-test/m/wild/t1", "nclink-test/m/wild/+", "m-wild"));
    // RabbitMQ keeps them in a store of the node that received them and
    // answers only an exact topic filter from it: nothing through another
    // node, nothing to a wildcard subscriber even on the same node.
    CHECK(retained_reaches(rabbit.url(0), rabbit.url(0), "nclink-test/r/state/t1", "nclink-test/r/state/t1", "r-exact"));
    CHECK_FALSE(retained_reaches(rabbit.url(0), rabbit.url(1), "nclink-test/r/other/t1", "nclink-test/r/other/t1", "r-other"));
    CHECK_FALSE(retained_reaches(rabbit.url(0), rabbit.url(0), "nclink-test/r/wild/t1", "nclink-test/r/wild/+", "r-wild"));

    // Last wills (MQTT 3.1.2.5) reach a subscriber on another node.
    CHECK(will_reaches(mosquitto.port(), m, "m"));
    CHECK(will_reaches(rabbit.mqtt_port(0), rabbit.url(1), "r"));

    // Shared subscriptions: mosquitto splits 20 messages over the two
    // members; RabbitMQ accepts the filter as a literal topic name, which
    // nothing is published to: none arrives.
    const SharedDelivery m_share = shared_delivery(m, m, "m");
    CHECK(m_share.total() == 20);
    CHECK(m_share.a > 0);
    CHECK(m_share.b > 0);
    const SharedDelivery r_share = shared_delivery(rabbit.url(0), rabbit.url(1), "r");
    CHECK(r_share.total() == 0);

    // MQTT 5: mosquitto accepts both levels; RabbitMQ 3.10 closes the
    // connection of a level-5 CONNECT without any CONNACK and accepts 3.1.1.
    const ConnectAnswer m5 = try_connect(mosquitto.port(), 5, "m-v5");
    CHECK(m5.connack);
    CHECK(m5.reason == 0);
    const ConnectAnswer r5 = try_connect(rabbit.mqtt_port(0), 5, "r-v5");
    CHECK_FALSE(r5.connack);
    CHECK(r5.closed);
    const ConnectAnswer r4 = try_connect(rabbit.mqtt_port(0), 4, "r-v4");
    CHECK(r4.connack);
    CHECK(r4.reason == 0);

    // Round trips (printed, not asserted: a figure of a shared, noisy box):
    // nclink's own measurement, both connections on one node.
    auto round_trip_ms = [](const std::string& url) {
        MqttOptions o;
        o.broker_url = url;
        o.client_id = "rtt";
        auto measured = measure_broker_round_trip(o, 20, 10s);
        REQUIRE(measured);
        auto relayed = measured->relayed;
        REQUIRE(!relayed.empty());
        std::sort(relayed.begin(), relayed.end());
        return relayed[relayed.size() / 2].count() / 1000.0;
    };
    std::printf("cluster round trip (QoS 1 request answered, median of 20): mosquitto %.2f ms, RabbitMQ node %.2f ms\n",
                round_trip_ms(m), round_trip_ms(rabbit.url(0)));

    std::printf(
        "cluster matrix: $share mosquitto %zu+%zu of 20, RabbitMQ %zu+%zu of 20; "
        "MQTT 5 CONNECT RabbitMQ: connack %d closed %d\n",
        m_share.a, m_share.b, r_share.a, r_share.b, r5.connack, r5.closed);
}
