// What a 3-node ejabberd cluster (Debian's 23.01, mod_mqtt) does with the MQTT
// features nclink relies on, measured with the probes the RabbitMQ cluster is
// measured with: the ejabberd column of the compatibility matrix in
// docs/scaling.md. Each CHECK states the broker's behaviour as measured, so
// an ejabberd version that changes it fails here and the matrix gets updated.
// Every client logs in (EjabberdCluster::username(), password()): mod_mqtt
// refuses a CONNECT without a password.
#include "cluster_probe.hpp"

#include <algorithm>
#include <cstdio>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

const std::string user = EjabberdCluster::username();
const std::string pass = EjabberdCluster::password();

std::unique_ptr<Probe> probe(const std::string& url, const std::string& id, bool clean_session = true, int mqtt_version = 4) {
    return std::make_unique<Probe>(url, id, clean_session, mqtt_version, user, pass);
}

// A retained message published through `pub_url` to `topic`; a new
// subscriber through `sub_url` to `filter`: did the retained message reach it?
bool retained_reaches(const std::string& pub_url, const std::string& sub_url, const std::string& topic, const std::string& filter,
                      const std::string& tag) {
    const std::string payload = "retained-" + tag;
    {
        auto pub = probe(pub_url, tag + "-pub");
        REQUIRE(pub->connected());
        REQUIRE(pub->transport->publish({topic, payload, 1, true}));
        REQUIRE(pub->transport->flush(5s));
    }
    auto sub = probe(sub_url, tag + "-sub");
    REQUIRE(sub->connected());
    REQUIRE(sub->subscribe_ready(filter, topic));
    // A retained message is sent right after the SUBACK, before the marker
    // (published after the SUBSCRIBE); a little grace all the same.
    std::this_thread::sleep_for(300ms);
    return sub->with_payload(payload) > 0;
}

// A client connects through `will_port` with a will and drops the TCP
// connection without DISCONNECT; does a subscriber on `sub_url` get the will?
bool will_reaches(int will_port, const std::string& sub_url, const std::string& tag) {
    const std::string topic = "nclink-test/" + tag + "/will";
    auto sub = probe(sub_url, tag + "-will-sub");
    REQUIRE(sub->connected());
    REQUIRE(sub->subscribe_ready(topic, topic));
    {
        RawPeer peer(will_port);
        Will will{topic, "gone-" + tag, 1};
        REQUIRE(peer.send(mqtt_connect(4, tag + "-will-client", &will, user, pass)));
        const std::string connack = peer.receive(3s, 4);
        REQUIRE(connack.size() == 4);
        REQUIRE(connack[3] == 0);
    }  // closed without DISCONNECT: the broker must publish the will (3.1.2.5)
    return eventually([&] { return sub->with_payload("gone-" + tag) > 0; }, 5s);
}

// A SUBSCRIBE (packet id 1, QoS 1) to `filter` on a raw connection logged in
// at protocol `level`: what the broker answered.
struct SubscribeAnswer {
    bool suback = false;         ///< a SUBACK came
    int granted = -1;            ///< its first return / reason code
    bool disconnect = false;     ///< an MQTT 5 DISCONNECT came instead
    int disconnect_reason = -1;  ///< its reason code
    bool closed = false;         ///< the broker closed the connection
};
SubscribeAnswer try_subscribe(int port, int level, const std::string& client_id, const std::string& filter) {
    RawPeer peer(port);
    REQUIRE(peer.send(mqtt_connect(level, client_id, nullptr, user, pass)));
    const std::string connack = peer.receive(3s, level == 5 ? 5 : 4);
    REQUIRE(connack.size() >= 4);
    REQUIRE(static_cast<unsigned char>(connack[0]) == 0x20);
    // The CONNACK of MQTT 5 carries properties: read them all before the SUBSCRIBE.
    if (level == 5) (void)peer.receive(300ms);
    std::string body{'\0', '\x01'};
    if (level == 5) body += '\0';  // no properties
    body += mqtt_string(filter) + '\x01';
    REQUIRE(peer.send(mqtt_packet(0x82, body)));
    const std::string got = peer.receive(3s, 5);
    SubscribeAnswer answer;
    if (!got.empty() && static_cast<unsigned char>(got[0]) == 0x90 && got.size() >= 5) {
        answer.suback = true;
        answer.granted = static_cast<unsigned char>(got[level == 5 ? 5 : 4]);
    }
    if (!got.empty() && static_cast<unsigned char>(got[0]) == 0xe0 && got.size() >= 3) {
        answer.disconnect = true;
        answer.disconnect_reason = static_cast<unsigned char>(got[2]);
    }
    answer.closed = peer.closed_within(answer.suback ? 300ms : 1s);
    return answer;
}

// Two subscribers of `$share/g/<topic>`, through `url_a` and `url_b` (nclink's
// transport: a connection the broker drops comes back and subscribes again);
// 20 QoS 1 messages to <topic>: how many reach them, and how often they
// connected meanwhile.
struct SharedDelivery {
    std::size_t a = 0, b = 0;
    std::uint64_t connects = 0;
    std::size_t total() const { return a + b; }
};
SharedDelivery shared_delivery(const std::string& url_a, const std::string& url_b, const std::string& tag) {
    const std::string topic = "nclink-test/" + tag + "/work";
    auto a = probe(url_a, tag + "-share-a");
    auto b = probe(url_b, tag + "-share-b");
    REQUIRE(a->connected());
    REQUIRE(b->connected());
    for (auto* p : {a.get(), b.get()}) REQUIRE(p->transport->subscribe({"$share/g/" + topic}, 1));
    std::this_thread::sleep_for(1s);
    auto pub = probe(url_a, tag + "-share-pub");
    REQUIRE(pub->connected());
    for (int i = 0; i < 20; ++i) REQUIRE(pub->transport->publish({topic, "job-" + std::to_string(i), 1, false}));
    REQUIRE(pub->transport->flush(5s));
    eventually([&] { return a->received_on(topic) + b->received_on(topic) >= 20; }, 3s);
    return {a->received_on(topic), b->received_on(topic), a->transport->stats().connects + b->transport->stats().connects};
}

}  // namespace

TEST_CASE("ejabberd cluster: logins, MQTT 5, retained messages, last wills and $share") {
    NCLINK_NEEDS_EJABBERD();
    const auto boot_began = std::chrono::steady_clock::now();
    EjabberdCluster ejabberd;
    const auto boot_took = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - boot_began);
    REQUIRE(ejabberd.size() == 3);

    // Logins: a CONNECT without user name and password is refused with
    // CONNACK 5 (not authorized) and closed; with them (anonymous login)
    // both protocol levels are accepted.
    const ConnectAnswer anonymous = try_connect(ejabberd.mqtt_port(0), 4, "e-anon");
    CHECK(anonymous.connack);
    CHECK(anonymous.reason == 5);
    CHECK(anonymous.closed);
    const ConnectAnswer e4 = try_connect(ejabberd.mqtt_port(0), 4, "e-v4", user, pass);
    CHECK(e4.connack);
    CHECK(e4.reason == 0);
    CHECK_FALSE(e4.closed);
    const ConnectAnswer e5 = try_connect(ejabberd.mqtt_port(1), 5, "e-v5", user, pass);
    CHECK(e5.connack);
    CHECK(e5.reason == 0);
    CHECK_FALSE(e5.closed);

    // Retained messages: delivered on the node that received them, to an
    // exact and a wildcard filter alike. Through another node, neither: the
    // payload is in a Mnesia table, but a SUBSCRIBE looks its topics up in an
    // index (an ETS table) of its own node, filled at the node's start and
    // by the retained PUBLISHes that node received.
    CHECK(retained_reaches(ejabberd.url(0), ejabberd.url(0), "nclink-test/e/state/t1", "nclink-test/e/state/t1", "e-exact"));
    CHECK(retained_reaches(ejabberd.url(0), ejabberd.url(0), "Notify/State/e-wild", "Notify/State/+", "e-wild"));
    CHECK_FALSE(retained_reaches(ejabberd.url(0), ejabberd.url(1), "nclink-test/e/other/t1", "nclink-test/e/other/t1", "e-other"));
    CHECK_FALSE(retained_reaches(ejabberd.url(0), ejabberd.url(2), "Notify/State/e-far", "Notify/State/+", "e-far"));

    // Last wills (MQTT 3.1.2.5) reach a subscriber on another node.
    CHECK(will_reaches(ejabberd.mqtt_port(0), ejabberd.url(1), "e"));

    // Shared subscriptions: not supported. A SUBSCRIBE to $share/... gets
    // no SUBACK; MQTT 3.1.1 connections are closed at once, MQTT 5 ones get a
    // DISCONNECT 0x9E (shared subscriptions not supported) first.
    const SubscribeAnswer share4 = try_subscribe(ejabberd.mqtt_port(0), 4, "e-share-4", "$share/g/nclink-test/e/work");
    CHECK_FALSE(share4.suback);
    CHECK_FALSE(share4.disconnect);
    CHECK(share4.closed);
    const SubscribeAnswer share5 = try_subscribe(ejabberd.mqtt_port(0), 5, "e-share-5", "$share/g/nclink-test/e/work");
    CHECK_FALSE(share5.suback);
    CHECK(share5.disconnect);
    CHECK(share5.disconnect_reason == 0x9e);
    CHECK(share5.closed);
    // A plain filter on the same kind of connection is granted QoS 1.
    const SubscribeAnswer plain = try_subscribe(ejabberd.mqtt_port(0), 4, "e-plain-4", "nclink-test/e/work");
    CHECK(plain.suback);
    CHECK(plain.granted == 1);
    CHECK_FALSE(plain.closed);
    // So two members through nclink's transport get none of 20 messages; their
    // connections are dropped at each SUBSCRIBE and come back (more than the
    // first two connects).
    const SharedDelivery share = shared_delivery(ejabberd.url(0), ejabberd.url(1), "e");
    CHECK(share.total() == 0);
    CHECK(share.connects > 2);

    // Round trip (printed, not asserted: a figure of a shared, noisy box):
    // nclink's own measurement, both connections on one node.
    MqttOptions o;
    o.broker_url = ejabberd.url(0);
    o.client_id = "rtt";
    o.username = user;
    o.password = pass;
    auto measured = measure_broker_round_trip(o, 20, 10s);
    REQUIRE(measured);
    auto relayed = measured->relayed;
    REQUIRE(!relayed.empty());
    std::sort(relayed.begin(), relayed.end());

    std::printf(
        "ejabberd matrix: boot and join of 3 nodes %lld ms, node 1 resident %ld KiB; QoS 1 request answered through one "
        "node (median of 20) %.2f ms; CONNECT without login: connack %d reason %d; MQTT 5 CONNECT reason %d; "
        "$share SUBSCRIBE 3.1.1: suback %d closed %d, 5: DISCONNECT 0x%02x; $share members %zu+%zu of 20 (%llu connects)\n",
        static_cast<long long>(boot_took.count()), ejabberd.resident_kib(0), relayed[relayed.size() / 2].count() / 1000.0,
        anonymous.connack, anonymous.reason, e5.reason, share4.suback, share4.closed,
        static_cast<unsigned>(share5.disconnect_reason), share.a, share.b, static_cast<unsigned long long>(share.connects));
}
