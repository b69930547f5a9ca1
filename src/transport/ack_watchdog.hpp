// Notices a broker connection that is up but no longer acknowledges: messages
// are in flight and none of them has been acknowledged (PUBACK, 3.4; or, at
// QoS 0, written) for `limit`. Keep-alive (3.1.2.10) cannot see this: it
// looks only for *some* packet from the broker, and a broker that keeps
// delivering requests while our window never drains looks alive to it. The
// adapter then answers nothing while it still receives every request
// (docs/performance.md "Request bursts": 64 answers unacknowledged, ~1,400
// queued behind them, for good).
// The transport treats such a link as dead: it drops the connection,
// reconnects and sends every unacknowledged message again (QoS 1 is at least
// once, 4.3.2), counted in TransportStats::stalled_links and logged.
//
// No clock of its own: every call is given the time, so tests drive it.
// Threading: not thread-safe; the libmosquitto transport calls it on its loop
// thread only, the paho transport under a mutex of its own (progress comes on
// paho's callback thread, the check on the supervisor).
#pragma once

#include <chrono>
#include <cstddef>

namespace nclink::transport_detail {

/// The limit a transport's watchdog uses: MqttOptions::ack_timeout when set,
/// else two keep-alive periods of the keep-alive the client really uses.
inline std::chrono::milliseconds ack_limit(std::chrono::milliseconds ack_timeout, std::chrono::seconds keep_alive) {
    if (ack_timeout.count() != 0) return ack_timeout;
    return 2 * std::chrono::duration_cast<std::chrono::milliseconds>(keep_alive);
}

class AckWatchdog {
public:
    using Clock = std::chrono::steady_clock;

    /// `limit` <= 0: never stalled (the check is off).
    explicit AckWatchdog(std::chrono::milliseconds limit) : limit_(limit) {}

    /// A new connection: nothing is owed on it yet.
    void connected(Clock::time_point now) { since_ = now; }
    /// Something in flight was acknowledged (or a QoS 0 message written).
    void progress(Clock::time_point now) { since_ = now; }
    /// Called periodically with what is in flight now. While nothing is in
    /// flight the link owes nothing and the clock restarts; so the time
    /// counted is from the later of the last progress and the moment the
    /// window last was empty (to within one check period).
    bool stalled(Clock::time_point now, std::size_t in_flight) {
        if (in_flight == 0 || limit_.count() <= 0) {
            since_ = now;
            return false;
        }
        return now - since_ >= limit_;
    }
    /// How long the window has waited for an acknowledgement (for the log).
    std::chrono::milliseconds waited(Clock::time_point now) const {
        return std::chrono::duration_cast<std::chrono::milliseconds>(now - since_);
    }
    std::chrono::milliseconds limit() const { return limit_; }

private:
    const std::chrono::milliseconds limit_;
    Clock::time_point since_{};
};

}  // namespace nclink::transport_detail
