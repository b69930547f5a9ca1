// What an MQTT transport does when a connection it had made is lost (or
// dropped by itself): one rule for both transports (the libmosquitto one and
// paho's), written once, as the back-off is (backoff.hpp).
//
// A connection lost before it was stable (ReconnectBackoff::lost(): it lived
// less than stable_after()) is a failed attempt, for the back-off and for the
// failover list alike: the next attempt goes to the next broker of the list
// (broker_list.hpp), as after an attempt that got no CONNACK. A broker that
// accepts the CONNECT (CONNACK, MQTT 3.1.1 3.2 / MQTT 5 3.2) and then drops
// the connection again and again otherwise held a terminal forever: a
// RabbitMQ 3.10 node whose client ids lived on a dead peer did exactly that
// (docs/scaling.md), with two healthy nodes further down the list. A
// connection that was stable and then lost is made again to the same broker
// first: a broker restart must not move a plant (docs/configuration.md,
// "Failover to other brokers").
#pragma once

#include "transport/backoff.hpp"
#include "transport/broker_list.hpp"

#include <chrono>

namespace nclink::transport_detail {

/// What connection_lost() decided.
struct AfterLoss {
    bool stable = false;                  ///< it lived stable_after(): the back-off starts again from reconnect_min
    std::chrono::milliseconds lasted{0};  ///< how long the connection was up
    bool moved = false;                   ///< the next attempt goes to the next broker (now brokers.current())
};

/// The connection to brokers.current(), made at backoff.connected(), was
/// lost (or dropped by us) at `now`. Updates the back-off (lost()) and, for a
/// connection that was not stable, moves the rotation on (no move when the
/// list has one broker). The caller owns both, as for ReconnectBackoff.
inline AfterLoss connection_lost(ReconnectBackoff& backoff, BrokerRotation& brokers, ReconnectBackoff::Clock::time_point now) {
    AfterLoss after;
    after.lasted = backoff.lasted(now);
    after.stable = backoff.lost(now);
    after.moved = !after.stable && brokers.advance();
    return after;
}

}  // namespace nclink::transport_detail
