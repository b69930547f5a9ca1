// The MQTT transport of libnclink, over libmosquitto (Debian libmosquitto-dev
// 2.0): the options every MQTT transport of nclink takes, and its factory.
// The plant library (libnclink-plant) has a paho transport with the same
// options (paho_transport.hpp); docs/building.md says why the terminal
// library has libmosquitto only.
#pragma once

#include <nclink/export.hpp>
#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace nclink {

struct NCLINK_API MqttTlsOptions {
    std::string ca_file;    ///< PEM trust store; empty = system default
    std::string cert_file;  ///< client certificate (PEM), for mutual TLS
    std::string key_file;   ///< client private key (PEM)
    std::string key_password;
    bool verify_server = true;  ///< check the broker's certificate and host name
};

struct NCLINK_API MqttOptions {
    /// tcp://host:port, ssl://host:port (TLS); ws:// and wss:// with the
    /// paho transport of libnclink-plant only (make_paho_transport()).
    std::string broker_url = "tcp://127.0.0.1:1883";
    /// Further brokers to fail over to, in order ("failover" in a broker
    /// section): "host:port" (the scheme of broker_url) or a URL as above.
    /// When an attempt to connect fails, or a lost connection cannot be made
    /// again to the same broker, the next attempt goes to the next broker of
    /// [broker_url, failover_urls...] (after the last: broker_url again),
    /// with the usual back-off. TLS, credentials, client id and last will
    /// are the same for each; every entry must use TLS exactly when
    /// broker_url does, and name a broker once. TransportStats::failovers
    /// counts the connections made to another broker than the last one.
    std::vector<std::string> failover_urls;
    std::string client_id;  ///< required; unique on the broker
    std::string username;   ///< empty = anonymous
    std::string password;
    std::optional<MqttTlsOptions> tls;  ///< used for ssl:// and wss:// URLs
    /// 4 = MQTT 3.1.1, 5 = MQTT 5, 0 = auto: MQTT 5, and 3.1.1 when the
    /// broker refuses a 5 CONNECT (closes the connection or answers
    /// "unsupported protocol version"; RabbitMQ 3.10, docs/scaling.md); the
    /// level a CONNACK accepted is kept for every reconnection to the same
    /// broker (a failover to another one of failover_urls tries 5 first again;
    /// paho, once connected at 3.1.1, keeps 3.1.1). Both transports.
    int mqtt_version = 4;
    bool clean_session = true;
    std::chrono::seconds keep_alive{20};
    std::chrono::milliseconds connect_timeout{5000};
    std::chrono::milliseconds reconnect_min{250};  ///< first retry delay, doubled per failure
    /// Retry delay cap; also how long a connection must stay up (at most
    /// 60 s) for its loss to start again from reconnect_min. A connection
    /// the broker accepts and drops sooner counts as a failed attempt (the
    /// delay doubles), so a broker that accepts and closes at once is not
    /// hit every reconnect_min. Both transports.
    std::chrono::milliseconds reconnect_max{10000};
    std::optional<Message> last_will;
    OutboxLimits outbox;
    /// Without TCP_NODELAY a QoS 1 round trip through mosquitto takes ~88 ms
    /// (Nagle meets delayed ACK) instead of ~0.5 ms. On by default
    /// (libmosquitto sets it on its socket; the paho transport finds paho's,
    /// src/transport/tcp_nodelay.cpp).
    bool tcp_nodelay = true;
    /// A connection with messages in flight of which none is acknowledged
    /// (PUBACK; at QoS 0: written) for this long is taken for dead although
    /// keep-alive still sees the broker: it is dropped and made again, and
    /// every unacknowledged message is sent again (TransportStats::
    /// stalled_links). 0 = two keep-alive periods (keep_alive, at least 5 s).
    /// Negative: never. Both transports (libmosquitto and paho).
    std::chrono::milliseconds ack_timeout{0};
};

/// Round trips through the broker, measured on two short-lived connections
/// of its own: `direct`, a QoS 0 message one connection publishes to itself
/// (one hop each way); `relayed`, a QoS 1 request from the first connection
/// that the second answers, as an NC-Link request and its response travel.
struct NCLINK_API BrokerRoundTrip {
    std::vector<std::chrono::microseconds> direct;
    std::vector<std::chrono::microseconds> relayed;
};

/// Measures `samples` round trips of each kind after a warm-up. The
/// connections use `options` with "-rtt-a" / "-rtt-b" appended to the client
/// id and no last will. Fails with ErrorCode::unavailable when the broker
/// cannot be reached, or a message does not come back, within `timeout`.
/// Blocks the caller; call it before serving, not from a handler.
NCLINK_API Result<BrokerRoundTrip> measure_broker_round_trip(MqttOptions options, int samples = 3,
                                                             std::chrono::milliseconds timeout = std::chrono::seconds(3));

/// One line naming the broker setting `set_tcp_nodelay true` when the
/// measurement shows the broker's Nagle delay: the relayed round trip tens of
/// milliseconds longer than two direct ones (the broker holds its answer back
/// until the peer acknowledges the previous packet, which the peer delays,
/// docs/performance.md); empty when it does not. Pure: no I/O.
NCLINK_API std::string broker_delay_warning(const BrokerRoundTrip& measured);

/// Whether `url` is a broker URL an MQTT transport of nclink can use; else a
/// value_type error saying what is wrong and showing the expected form
/// ("SCHEME://HOST[:PORT]"). Checks the text only, connects nowhere.
NCLINK_API Result<void> check_broker_url(const std::string& url);

/// Creates the MQTT transport of libnclink: libmosquitto, its socket served
/// by an I/O thread of its own ("nclink-mqtt-io", which runs every callback
/// of the transport). Fails with ErrorCode::parameter_missing / value_type
/// for unusable options: no client id, a bad URL, a ws:// or wss:// URL
/// (the paho transport of libnclink-plant speaks those), an ssl:// URL in a
/// build without TLS (NCLINK_WITH_TLS=OFF, docs/building.md).
NCLINK_API Result<std::unique_ptr<Transport>> make_mqtt_transport(MqttOptions options, Logger logger = {});

}  // namespace nclink
