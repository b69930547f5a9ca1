// The MQTT transport of libnclink: libmosquitto, its socket served by an
// MqttLoop. A gateway's machines share one loop (one epoll thread for all of
// their connections); make_mqtt_transport() gives a single adapter a loop of
// its own. The contract of transport.hpp, for tcp:// and ssl:// brokers;
// ws:// and wss:// are the paho transport's (libnclink-plant).
#pragma once

#include <nclink/mqtt_transport.hpp>

#include <memory>

namespace nclink::core_detail {
class PollHost;
}

namespace nclink::transport_detail {

class MqttLoop;

/// Whether the multiplexed transport can reach `broker_url` (tcp, mqtt, ssl, mqtts).
bool mosquitto_supports(const std::string& broker_url);

/// `work`: the shared work threads its outbox's sender runs on (a
/// gateway's, core/serial_work.hpp), or null for a sender thread of its own.
Result<std::unique_ptr<Transport>> make_mosquitto_transport(MqttOptions options, Logger logger, std::shared_ptr<MqttLoop> loop,
                                                            core_detail::PollHost* work = nullptr);

/// make_mqtt_transport() (a loop of its own, one I/O thread) with its
/// outbox's sender on `work` (a gateway's shared work threads; null: a
/// thread of its own, as make_mqtt_transport()).
Result<std::unique_ptr<Transport>> make_own_loop_transport(MqttOptions options, Logger logger, core_detail::PollHost* work);

}  // namespace nclink::transport_detail
