// The rule both MQTT transports follow when a connection they had made is
// lost (src/transport/connection_lost.hpp), with injected times: lost before
// it was stable, it moves to the next broker of the failover list as a
// failed attempt does; lost after, it stays for the same broker.
#include "transport/connection_lost.hpp"

#include <catch2/catch.hpp>

using namespace nclink::transport_detail;
using namespace std::chrono_literals;

namespace {

const ReconnectBackoff::Clock::time_point t0{std::chrono::hours(1)};

BrokerRotation three_nodes() {
    auto list = broker_list("tcp://node1:1883", {"node2:1883", "node3:1883"});
    REQUIRE(list);
    return BrokerRotation(std::move(list).value());
}

}  // namespace

TEST_CASE("connection lost: one dropped right after its CONNACK moves to the next broker, and the back-off doubles") {
    BrokerRotation brokers = three_nodes();
    ReconnectBackoff backoff(50ms, 800ms);
    // A node that accepts each CONNECT and drops the connection 5 ms later
    // (RabbitMQ 3.10 with a dead peer, docs/scaling.md): before, the
    // transport stayed on it forever.
    backoff.connected(t0);
    const AfterLoss after = connection_lost(backoff, brokers, t0 + 5ms);
    CHECK_FALSE(after.stable);
    CHECK(after.moved);
    CHECK(after.lasted == 5ms);
    CHECK(brokers.current().url == "tcp://node2:1883");
    CHECK(backoff.delay() == 100ms);

    // Node 2 does the same: on to node 3, then round to node 1.
    backoff.connected(t0 + 1s);
    CHECK(connection_lost(backoff, brokers, t0 + 1s + 799ms).moved);  // just short of stable (800 ms)
    CHECK(brokers.current().url == "tcp://node3:1883");
    CHECK(backoff.delay() == 200ms);
    backoff.connected(t0 + 3s);
    CHECK(connection_lost(backoff, brokers, t0 + 3s + 1ms).moved);
    CHECK(brokers.current().url == "tcp://node1:1883");
}

TEST_CASE("connection lost: one that was stable is made again to the same broker first, from the shortest back-off") {
    BrokerRotation brokers = three_nodes();
    ReconnectBackoff backoff(50ms, 800ms);
    for (int i = 0; i < 3; ++i) backoff.failed();
    // A broker restart drops a connection that served for a while: the plant
    // stays on its broker (docs/configuration.md, "When it moves").
    backoff.connected(t0);
    const AfterLoss after = connection_lost(backoff, brokers, t0 + 800ms);
    CHECK(after.stable);
    CHECK_FALSE(after.moved);
    CHECK(brokers.current().url == "tcp://node1:1883");
    CHECK(backoff.delay() == 50ms);
}

TEST_CASE("connection lost: with one broker a short connection has nowhere to move and only grows the back-off") {
    auto list = broker_list("tcp://only:1883", {});
    REQUIRE(list);
    BrokerRotation brokers(std::move(list).value());
    ReconnectBackoff backoff(50ms, 800ms);
    backoff.connected(t0);
    const AfterLoss after = connection_lost(backoff, brokers, t0 + 5ms);
    CHECK_FALSE(after.stable);
    CHECK_FALSE(after.moved);
    CHECK(brokers.current().url == "tcp://only:1883");
    CHECK(backoff.delay() == 100ms);
}
