// The floor of a request round trip, shared by the benchmarks that compare
// nclink's answer with it: a bare paho client that answers every request at
// once, from inside paho's message callback, in a process of its own. What it
// answers comes from `Answer`; it never parses more than that needs.
#pragma once

#include "transport/tcp_nodelay.hpp"

#include <mqtt/async_client.h>

#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

namespace nclink::bench {

/// `username`/`password`: the login where the broker wants one (an ejabberd cluster).
inline void connect_and_subscribe(mqtt::async_client& client, const std::string& topic, int port,
                                  const std::string& username = "", const std::string& password = "") {
    auto builder = mqtt::connect_options_builder().clean_session(true).mqtt_version(MQTTVERSION_3_1_1);
    if (!username.empty()) builder.user_name(username).password(password);
    auto options = builder.finalize();
    if (!client.connect(options)->wait_for(std::chrono::seconds(10)))
        throw std::runtime_error("connect of " + client.get_client_id() + " timed out");
    // The broker's end of this connection, as nclink's own transports do
    // (docs/performance.md, "Broker"): the floor must not pay a Nagle delay
    // the adapter does not.
    transport_detail::apply_tcp_nodelay_to_peer("127.0.0.1", port);
    if (!client.subscribe(topic, 1)->wait_for(std::chrono::seconds(10)))
        throw std::runtime_error("subscribe of " + client.get_client_id() + " timed out");
}

class PahoEcho {
public:
    /// Publishes the answer to `request` with `client`. Called on paho's
    /// callback thread, one request at a time.
    using Answer = std::function<void(const mqtt::message& request, mqtt::async_client& client)>;

    PahoEcho(const std::string& url, const std::string& client_id, const std::string& request_topic, int port, Answer answer,
             const std::string& username = "", const std::string& password = "")
        : client_(url, client_id, mqtt::create_options(MQTTVERSION_3_1_1), nullptr), answer_(std::move(answer)) {
        client_.set_message_callback([this](mqtt::const_message_ptr m) { answer_(*m, client_); });
        connect_and_subscribe(client_, request_topic, port, username, password);
    }
    ~PahoEcho() { client_.disconnect()->wait(); }
    PahoEcho(const PahoEcho&) = delete;
    PahoEcho& operator=(const PahoEcho&) = delete;

private:
    mqtt::async_client client_;
    Answer answer_;
};

}  // namespace nclink::bench
