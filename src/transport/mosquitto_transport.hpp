// The MQTT transport of libnclink: libmosquitto, its socket served by an
// MqttLoop. A gateway's machines share one loop (one epoll thread for all of
// their connections); make_mqtt_transport() gives a single adapter a loop of
// its own. The contract of transport.hpp, for tcp:// and ssl:// brokers;
// ws:// and wss:// are the paho transport's (libnclink-plant).
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
