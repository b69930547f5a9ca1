// One check for every MQTT transport against a broker that accepts each
// connection (CONNACK) and closes it soon after, as a RabbitMQ 3.10 node did
// while its peer was dead (docs/scaling.md): the stand-in of
// support/mqtt5_refusing_broker.hpp on a loopback port, counting the
// CONNECTs it reads. The back-off must grow as for refused attempts
// (src/transport/backoff.hpp), not start again at each CONNACK (before:
// about four reconnects a second, forever). Used by the libmosquitto test
// (tests/unit/transport) and the paho one (tests/unit/paho).
#pragma once

#include <nclink/mqtt_transport.hpp>

#include "support/mqtt5_refusing_broker.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <thread>

namespace nclink::test {

/// `make` builds the transport under test from `options` (broker URL and a
/// 50-800 ms back-off filled in; `tweak` adjusts the rest).
inline void check_backoff_on_flapping_broker(Mqtt5RefusingBroker& broker,
                                             const std::function<Result<std::unique_ptr<Transport>>(MqttOptions)>& make,
                                             const std::function<void(MqttOptions&)>& tweak = {}) {
    using namespace std::chrono_literals;
    MqttOptions o;
    o.broker_url = broker.url();
    o.reconnect_min = 50ms;
    o.reconnect_max = 800ms;
    if (tweak) tweak(o);
    auto made = make(o);
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return broker.connects() >= 1; }, 10s));

    // Counted over 4 s from the first CONNECT. Growing (waits drawn from
    // [50,100], [100,200], [200,400], then [400,800] ms): 13 attempts at the
    // very most, fewer on a loaded machine. Starting again from 50 ms at each
    // CONNACK (waits of 25-50 ms) made about 40 with libmosquitto. (paho
    // itself takes about a second between its TCP connection and its
    // CONNECT, so there the count alone tells little; the waits below do.)
    std::this_thread::sleep_for(4s);
    const std::size_t attempts = broker.connects();
    const std::uint64_t connects = transport.stats().connects;
    INFO("CONNECTs read in 4 s: " << attempts << ", connections counted: " << connects);
    CHECK(attempts <= 16);
    CHECK(attempts >= 2);  // and it does keep trying (the waits below: at least five)
    CHECK(connects <= 16);
    // The waits between a close and the next connection, as the broker saw
    // them (so a loaded machine can only make them longer): drawn from
    // [50,100], [100,200], [200,400], then [400,800] ms. Starting again at
    // each CONNACK kept every one at 25-50 ms.
    REQUIRE(eventually([&] { return broker.reconnect_waits().size() >= 4; }, 20s));
    const auto waits = broker.reconnect_waits();
    INFO("waits: " << waits[0].count() << ", " << waits[1].count() << ", " << waits[2].count() << ", " << waits[3].count()
                   << " ms");
    CHECK(waits[3] >= 350ms);

    // The broker heals: the next attempt, at most reconnect_max away, stays up
    // (a connection whose CONNACK went out before is still closed).
    const std::size_t before = broker.close_after_connack(false);
    REQUIRE(eventually([&] { return broker.connects() > before && transport.state() == LinkState::connected; }, 10s));
    std::this_thread::sleep_for(200ms);
    CHECK(transport.state() == LinkState::connected);
    transport.stop(0ms);
}

}  // namespace nclink::test
