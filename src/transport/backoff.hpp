// The wait before the next connect attempt of an MQTT transport (both: the
// libmosquitto one and paho's; one rule, written once).
//
// Exponential: each failed attempt doubles the back-off, from reconnect_min
// up to reconnect_max. Jittered: a broker restart drops every terminal of a
// plant at the same instant, and without jitter they all retry in lockstep
// (1,000 gateway machines timed out together round after round). The wait is
// spread over [delay/2, delay].
//
// A connection that the broker accepted (CONNACK, MQTT 3.1.1 3.2 / MQTT 5
// 3.2) and then dropped before it was stable counts as a failed attempt: its
// loss doubles the back-off too. Only a connection that stayed up for
// stable_after() starts it again from reconnect_min. When every CONNACK
// started it again, a broker that accepts and then closes at once (a RabbitMQ
// 3.10 node whose peer died, measured in docs/scaling.md; a broker that
// kicks the session at SUBSCRIBE) had every terminal reconnect after its
// shortest back-off, about four times a second, forever.
#pragma once

#include <algorithm>
#include <chrono>
#include <random>

namespace nclink::transport_detail {

inline std::chrono::milliseconds jittered(std::chrono::milliseconds delay, std::mt19937& rng) {
    if (delay.count() <= 1) return delay;
    std::uniform_int_distribution<std::chrono::milliseconds::rep> spread(delay.count() / 2, delay.count());
    return std::chrono::milliseconds(spread(rng));
}

/// The longest a connection has to stay up to count as stable, whatever
/// reconnect_max is: one that served for a minute (three keep-alive periods
/// at the default 20 s, MQTT 3.1.2.10) is a working link, not a flapping one.
constexpr std::chrono::milliseconds kStableConnectionCap{60000};

/// How long a connection must stay up for its loss to start the back-off
/// again from reconnect_min: as long as the back-off cap (at most
/// kStableConnectionCap). With this rule no behaviour of a broker makes a
/// terminal reconnect more often than one that refuses every attempt: a
/// connection either lived reconnect_max, or its loss is followed by waits
/// that grow to reconnect_max, as failed attempts are. A fixed period of a
/// second or two would lose that bound for every cap above it: with the
/// default 10 s cap, a node that drops each connection after 3 s would be hit
/// every 3 s instead of every 5-10 s. Not an MqttOptions field:
/// reconnect_max already says how often a terminal may come back, and a
/// field would change a public struct's layout (docs/abi.md).
inline std::chrono::milliseconds stable_after(std::chrono::milliseconds reconnect_max) {
    return std::min(reconnect_max, kStableConnectionCap);
}

/// The back-off of one transport. Not thread-safe: its reconnecting thread
/// (the libmosquitto transport's loop thread, the paho transport's
/// supervisor) owns it. Times come from the caller, so tests inject them.
class ReconnectBackoff {
public:
    using Clock = std::chrono::steady_clock;

    ReconnectBackoff(std::chrono::milliseconds reconnect_min, std::chrono::milliseconds reconnect_max)
        : min_(reconnect_min), max_(reconnect_max), delay_(reconnect_min) {}

    /// The back-off now, before jitter.
    std::chrono::milliseconds delay() const { return delay_; }
    /// The wait before the next attempt: the back-off, jittered.
    std::chrono::milliseconds wait(std::mt19937& rng) const { return jittered(delay_, rng); }

    /// An attempt failed (no CONNACK, or a refusing one): the back-off doubles.
    void failed() { delay_ = std::min(delay_ * 2, max_); }

    /// A CONNACK accepted the connection at `now`. The back-off stays where
    /// it is until the connection proves stable (lost()).
    void connected(Clock::time_point now) { connected_at_ = now; }

    /// The connection made at connected() was lost (or dropped by us) at
    /// `now`. A stable one starts the back-off again from reconnect_min;
    /// one that lived less than stable_after() is a failed attempt (doubles).
    /// True when it was stable.
    bool lost(Clock::time_point now) {
        if (now - connected_at_ >= stable_after(max_)) {
            delay_ = min_;
            return true;
        }
        failed();
        return false;
    }

    /// How long the last connection lasted, when lost at `now`.
    std::chrono::milliseconds lasted(Clock::time_point now) const {
        return std::chrono::duration_cast<std::chrono::milliseconds>(now - connected_at_);
    }
    std::chrono::milliseconds stable_period() const { return stable_after(max_); }

private:
    const std::chrono::milliseconds min_;
    const std::chrono::milliseconds max_;
    std::chrono::milliseconds delay_;
    Clock::time_point connected_at_{};
};

}  // namespace nclink::transport_detail
