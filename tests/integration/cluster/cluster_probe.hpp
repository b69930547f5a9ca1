// What the cluster tests measure a broker with: a client on nclink's own MQTT
// transport (libmosquitto, MQTT 3.1.1 unless told), and raw MQTT packets for
// what a client library would hide (a CONNECT of a given protocol level, a
// connection dropped without DISCONNECT so the broker publishes its will).
// Only the test folder uses them.
#pragma once

#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>

#include "support/ejabberd_cluster.hpp"
#include "support/inbox.hpp"
#include "support/rabbitmq_cluster.hpp"
#include "support/raw_peer.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

namespace nclink::test {

/// Skips the test (a WARN naming why, then return) when the broker of
/// `Cluster` (RabbitCluster, EjabberdCluster) is not installed.
#define NCLINK_NEEDS_CLUSTER(Cluster)                                  \
    do {                                                               \
        const std::string why_skipped = Cluster::unavailable_reason(); \
        if (!why_skipped.empty()) {                                    \
            WARN(why_skipped);                                         \
            return;                                                    \
        }                                                              \
    } while (false)
#define NCLINK_NEEDS_RABBITMQ() NCLINK_NEEDS_CLUSTER(nclink::test::RabbitCluster)
#define NCLINK_NEEDS_EJABBERD() NCLINK_NEEDS_CLUSTER(nclink::test::EjabberdCluster)

/// How a program logs in to a cluster: RabbitMQ takes anonymous clients
/// (Login{}), ejabberd's mod_mqtt refuses a CONNECT without a password
/// (ejabberd_login()). One test body serves both clusters with it.
struct Login {
    std::string username;
    std::string password;
};

inline Login ejabberd_login() { return {EjabberdCluster::username(), EjabberdCluster::password()}; }

inline Logger probe_logger() { return std::getenv("NCLINK_TEST_LOG") ? Logger(stderr_sink(), LogLevel::debug) : Logger{}; }

/// A Query of the test adapter's `pos` (FakeDriver: 12.5) answered within
/// `patience`, asked again until it is: a SUBSCRIBE may still be on its way
/// through the cluster.
inline bool query_answered(Client& client, std::chrono::milliseconds patience) {
    RequestOptions quick;
    quick.timeout = std::chrono::seconds(2);
    return eventually(
        [&] {
            auto answer = client.query("test-dev", {{"pos", std::nullopt}}, quick);
            return answer.ok() && answer->size() == 1 && (*answer)[0].values && *(*answer)[0].values == Json::array({12.5});
        },
        patience);
}

/// One MQTT client on nclink's transport, with what it received.
struct Probe {
    Inbox inbox;
    std::unique_ptr<Transport> transport;

    /// `username`/`password`: the login where the broker wants one (ejabberd).
    Probe(const std::string& url, const std::string& id, bool clean_session = true, int mqtt_version = 4,
          const std::string& username = "", const std::string& password = "") {
        MqttOptions o;
        o.username = username;
        o.password = password;
        o.broker_url = url;
        o.client_id = id;
        o.clean_session = clean_session;
        o.mqtt_version = mqtt_version;
        o.reconnect_min = std::chrono::milliseconds(50);
        o.reconnect_max = std::chrono::milliseconds(500);
        auto made = make_mqtt_transport(o, probe_logger());
        if (!made) throw std::runtime_error("cannot make a transport: " + made.error().message);
        transport = std::move(*made);
        inbox.attach(*transport);
        if (!transport->start()) throw std::runtime_error("cannot start a transport");
    }
    ~Probe() {
        transport->stop(std::chrono::milliseconds(500));
        inbox.attached = nullptr;  // the transport goes first (declared last)
    }

    bool connected(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
        return eventually([&] { return transport->state() == LinkState::connected; }, timeout);
    }
    /// Subscribes and returns once the subscription works: a marker (payload
    /// "marker", QoS 0, not retained) published to `marker_topic`, which the
    /// filter must match, came back. The broker handles one connection's
    /// packets in order, so every SUBSCRIBE sent before this one is done too.
    bool subscribe_ready(const std::string& filter, const std::string& marker_topic) {
        if (!transport->subscribe({filter}, 1)) return false;
        return eventually(
            [&] {
                (void)transport->publish({marker_topic, "marker", 0, false});  // QoS 0: a lost one is sent again
                return eventually([&] { return with_payload("marker") > 0; }, std::chrono::milliseconds(200));
            },
            std::chrono::seconds(10));
    }
    std::size_t with_payload(const std::string& payload) {
        std::lock_guard<std::mutex> lock(inbox.mutex);
        return static_cast<std::size_t>(
            std::count_if(inbox.messages.begin(), inbox.messages.end(), [&](const Message& m) { return m.payload == payload; }));
    }
    std::size_t received_on(const std::string& topic) {
        std::lock_guard<std::mutex> lock(inbox.mutex);
        return static_cast<std::size_t>(std::count_if(inbox.messages.begin(), inbox.messages.end(), [&](const Message& m) {
            return m.topic == topic && m.payload != "marker";
        }));
    }
};

// Raw MQTT (MQTT 3.1.1 clause 3.1, MQTT 5.0 clause 3.1: CONNECT).
inline std::string mqtt_string(const std::string& s) {
    return std::string{static_cast<char>(s.size() >> 8), static_cast<char>(s.size() & 0xff)} + s;
}

inline std::string mqtt_packet(unsigned char type, const std::string& body) {
    std::string out(1, static_cast<char>(type));
    std::size_t length = body.size();
    do {
        unsigned char byte = length % 128;
        length /= 128;
        if (length > 0) byte |= 0x80;
        out += static_cast<char>(byte);
    } while (length > 0);
    return out + body;
}

struct Will {
    std::string topic;
    std::string payload;
    int qos = 1;
};

/// A CONNECT of protocol level 4 (3.1.1) or 5, clean start, keep-alive 30 s,
/// optionally with a will and a user name and password.
inline std::string mqtt_connect(int level, const std::string& client_id, const Will* will = nullptr,
                                const std::string& username = "", const std::string& password = "") {
    unsigned char flags = 0x02;
    if (will) flags |= static_cast<unsigned char>(0x04 | (will->qos << 3));
    if (!username.empty()) flags |= 0x80;
    if (!password.empty()) flags |= 0x40;
    std::string body = mqtt_string("MQTT") + static_cast<char>(level) + static_cast<char>(flags) + '\0' + '\x1e';
    if (level == 5) body += '\0';  // no properties
    body += mqtt_string(client_id);
    if (will) {
        if (level == 5) body += '\0';  // no will properties
        body += mqtt_string(will->topic) + mqtt_string(will->payload);
    }
    if (!username.empty()) body += mqtt_string(username);
    if (!password.empty()) body += mqtt_string(password);
    return mqtt_packet(0x10, body);
}

/// What a broker answered a raw CONNECT with.
struct ConnectAnswer {
    bool connack = false;  ///< a CONNACK came
    int reason = -1;       ///< its return / reason code
    bool closed = false;   ///< the broker closed the connection
};

inline ConnectAnswer try_connect(int port, int level, const std::string& client_id, const std::string& username = "",
                                 const std::string& password = "") {
    RawPeer peer(port);
    ConnectAnswer answer;
    if (!peer.connected() || !peer.send(mqtt_connect(level, client_id, nullptr, username, password))) return answer;
    const std::string got = peer.receive(std::chrono::seconds(3), 4);
    answer.connack = got.size() >= 4 && static_cast<unsigned char>(got[0]) == 0x20;
    if (answer.connack) answer.reason = static_cast<unsigned char>(got[3]);
    // After the CONNACK: is the connection kept? Without one: did the broker
    // close it (receive() saw the end) rather than keep it waiting?
    answer.closed = peer.closed_within(std::chrono::milliseconds(answer.connack ? 300 : 0));
    return answer;
}

}  // namespace nclink::test
