// An MQTT transport on libmosquitto whose socket is served by a shared
// MqttLoop: what a gateway's machines use (one epoll thread for all of their
// connections instead of paho's one polling thread per process). Same
// contract and options as make_mqtt_transport() (transport.hpp), for tcp://
// and ssl:// brokers; ws:// and wss:// stay with paho.
#pragma once

#include <nclink/mqtt_transport.hpp>

#include <memory>

namespace nclink::detail {

class MqttLoop;

/// Whether the multiplexed transport can reach `broker_url` (tcp, mqtt, ssl, mqtts).
bool mosquitto_supports(const std::string& broker_url);

Result<std::unique_ptr<Transport>> make_mosquitto_transport(MqttOptions options, Logger logger,
                                                            std::shared_ptr<MqttLoop> loop);

}  // namespace nclink::detail
