// The MQTT transport of the plant library (libnclink-plant): paho-mqtt-cpp
// (Debian libpaho-mqttpp-dev 1.2). The application client, the agent and the
// bridge run on it: it speaks ws:// and wss:// besides tcp:// and ssl://, and
// reads the broker's MQTT 5 Receive Maximum. Controller firmware does not
// need it: make_mqtt_transport() (mqtt_transport.hpp, libnclink) is the
// libmosquitto transport with the same options and contract
// (docs/building.md, "One MQTT client library").
#pragma once

#include <nclink/export.hpp>
#include <nclink/mqtt_transport.hpp>

namespace nclink {

/// Creates a paho MQTT transport: the contract of transport.hpp and every
/// field of MqttOptions. Fails with ErrorCode::parameter_missing /
/// value_type for unusable options (no client id, bad URL). Its callbacks
/// run on paho's callback thread.
NCLINK_API Result<std::unique_ptr<Transport>> make_paho_transport(MqttOptions options, Logger logger = {});

}  // namespace nclink
