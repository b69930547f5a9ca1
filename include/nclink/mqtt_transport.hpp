// MQTT transport over paho-mqtt-cpp (Debian libpaho-mqttpp-dev 1.2).
#pragma once

#include <nclink/export.hpp>
#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <string>

namespace nclink {

struct NCLINK_API MqttTlsOptions {
    std::string ca_file;        ///< PEM trust store; empty = system default
    std::string cert_file;      ///< client certificate (PEM), for mutual TLS
    std::string key_file;       ///< client private key (PEM)
    std::string key_password;
    bool verify_server = true;  ///< check the broker's certificate and host name
};

struct NCLINK_API MqttOptions {
    /// tcp://host:port, ssl://host:port (TLS), ws://, wss://.
    std::string broker_url = "tcp://127.0.0.1:1883";
    std::string client_id;                 ///< required; unique on the broker
    std::string username;                  ///< empty = anonymous
    std::string password;
    std::optional<MqttTlsOptions> tls;     ///< used for ssl:// and wss:// URLs
    int mqtt_version = 4;                  ///< 4 = MQTT 3.1.1, 5 = MQTT 5
    bool clean_session = true;
    std::chrono::seconds keep_alive{20};
    std::chrono::milliseconds connect_timeout{5000};
    std::chrono::milliseconds reconnect_min{250};   ///< first retry delay, doubled per failure
    std::chrono::milliseconds reconnect_max{10000}; ///< retry delay cap
    std::optional<Message> last_will;
    OutboxLimits outbox;
    /// paho C 1.3.12 never sets TCP_NODELAY; without it a QoS 1 round trip
    /// through mosquitto takes ~88 ms (Nagle meets delayed ACK) instead of
    /// ~0.5 ms. On by default; see src/transport/tcp_nodelay.cpp for how.
    bool tcp_nodelay = true;
};

/// Creates an MQTT transport. Fails with ErrorCode::parameter_missing /
/// value_type for unusable options (no client id, bad URL).
NCLINK_API Result<std::unique_ptr<Transport>> make_mqtt_transport(MqttOptions options, Logger logger = {});

}  // namespace nclink
