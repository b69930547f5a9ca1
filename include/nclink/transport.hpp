// The link between an NC-Link terminal and the broker: publish, subscribe,
// connection state. Implementations: MQTT over libmosquitto (mqtt_transport.hpp,
// libnclink), MQTT over paho (paho_transport.hpp, libnclink-plant) and an
// in-process loopback for tests (loopback_transport.hpp). The transport knows
// nothing of DTUs.
#pragma once

#include <nclink/export.hpp>
#include <nclink/result.hpp>
#include <nclink/topic_filter.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

struct NCLINK_API Message {
    std::string topic;
    std::string payload;
    int qos = 1;
    bool retained = false;
};

enum class LinkState { disconnected, connecting, connected };

NCLINK_API std::string_view to_string(LinkState state) noexcept;

/// What the transport has done so far. Counters only grow.
struct NCLINK_API TransportStats {
    std::uint64_t published = 0;  ///< messages handed to the broker connection
    std::uint64_t received = 0;   ///< messages delivered to the message handler
    std::uint64_t dropped = 0;    ///< oldest messages dropped because the offline buffer was full
    std::uint64_t dropped_bytes = 0;
    std::uint64_t connects = 0;  ///< successful (re)connections
    std::size_t buffered = 0;    ///< messages waiting (offline, or queued behind the in-flight window)
    std::size_t buffered_bytes = 0;
    std::size_t in_flight = 0;           ///< handed to the connection, not yet acknowledged
    int tcp_nodelay_sockets = 0;         ///< sockets TCP_NODELAY was applied to at the last connect (MQTT)
    std::uint64_t connect_failures = 0;  ///< connection attempts that failed
    /// Reconnections of a persistent session (clean_session false) that found
    /// no session kept by the broker: what it queued for this client while it
    /// was away is gone (the broker restarted without working persistence, or
    /// expired the session). Logged as a warning each time.
    std::uint64_t sessions_lost = 0;
    /// Why the last connection attempt failed, one line ("" once connected):
    /// e.g. "the broker refused the user name or password", "the broker's
    /// certificate did not verify: certificate has expired".
    std::string last_error;
    /// The last attempt was refused (credentials, authorisation, a certificate; with failover_urls:
    /// the last attempt to every broker of the list was): retrying will not help until the
    /// configuration changes. Programs exit on it at start (docs/security.md).
    bool refused = false;
    /// Connections dropped (and made again, every unacknowledged message sent
    /// again) because messages were in flight and the broker acknowledged
    /// none of them within MqttOptions::ack_timeout while the link otherwise
    /// looked alive. Logged as a warning each time (docs/delivery.md).
    std::uint64_t stalled_links = 0;
    /// Connections made to another broker of the failover list
    /// (MqttOptions::failover_urls) than the one of the connection before
    /// (the first: than broker_url). Logged as a warning each time.
    std::uint64_t failovers = 0;
    /// The broker connected to, or tried next while the link is down (a URL
    /// of the failover list, broker_url before the first attempt; "" for
    /// transports without a broker).
    std::string broker;
};

/// Called for every message matching a subscription.
/// Thread: the transport's callback thread (its I/O thread, paho's, or the loopback broker's),
/// one message at a time, in arrival order. It must not block: decode and hand
/// work over. It may call publish()/subscribe().
using MessageHandler = std::function<void(const Message&)>;

/// Called when the link changes state; `detail` says why (for logs).
/// Thread: the transport's callback or supervisor thread; never concurrently
/// with itself. Must not block. It may call publish()/subscribe().
using LinkStateHandler = std::function<void(LinkState, std::string_view detail)>;

/// Thread-safety: publish(), subscribe(), unsubscribe(), state() and stats()
/// may be called from any thread, concurrently. Handlers must be set before
/// start(). start()/stop() are called by the owner, once each, not from a
/// handler.
class NCLINK_API Transport {
public:
    virtual ~Transport() = default;

    virtual void set_message_handler(MessageHandler handler) = 0;
    virtual void set_state_handler(LinkStateHandler handler) = 0;

    /// Starts connecting in the background and keeps the link up (reconnecting
    /// with backoff) until stop(). Fails only on unusable options.
    virtual Result<void> start() = 0;

    /// Sends what is buffered (waiting at most `flush_timeout`), disconnects
    /// cleanly (no last will), and joins every thread it started.
    virtual void stop(std::chrono::milliseconds flush_timeout = std::chrono::milliseconds(2000)) = 0;

    /// Queues a message. Messages go out in publish order. While the link is
    /// down they wait in a bounded buffer (oldest dropped first, counted in
    /// stats) and are sent, in order, after reconnecting. A QoS >= 1 message is
    /// kept until the broker acknowledges it and sent again if the link drops
    /// first (at-least-once: a receiver may see it twice).
    /// Fails with ErrorCode::memory_configured (404) only for a message larger
    /// than the whole buffer, and with ErrorCode::unavailable after stop().
    virtual Result<void> publish(Message message) = 0;

    /// Subscribes now if connected, and again after every reconnect.
    virtual Result<void> subscribe(std::vector<std::string> filters, int qos = 1) = 0;
    virtual Result<void> unsubscribe(std::vector<std::string> filters) = 0;

    virtual LinkState state() const = 0;
    virtual TransportStats stats() const = 0;

    /// Blocks until every buffered message has been handed over and
    /// acknowledged, or the timeout passes. Returns true when drained.
    virtual bool flush(std::chrono::milliseconds timeout) = 0;
};

/// Sizes of the buffer that holds messages while the link is down or busy.
struct NCLINK_API OutboxLimits {
    std::size_t max_bytes = 8u << 20;  ///< topic + payload bytes kept at most
    std::size_t max_in_flight = 64;    ///< messages handed to the connection and not yet acknowledged
};

}  // namespace nclink
