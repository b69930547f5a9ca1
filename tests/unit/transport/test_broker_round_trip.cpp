// The broker-delay check decides on measured round trips; these inject the
// measurements (no wall-clock), as taken through a broker with and without
// TCP_NODELAY.
#include <nclink/mqtt_transport.hpp>

#include <catch2/catch.hpp>

using namespace nclink;
using std::chrono::microseconds;

namespace {
BrokerRoundTrip trips(std::vector<long> direct_us, std::vector<long> relayed_us) {
    BrokerRoundTrip t;
    for (long v : direct_us) t.direct.push_back(microseconds(v));
    for (long v : relayed_us) t.relayed.push_back(microseconds(v));
    return t;
}
}  // namespace

TEST_CASE("broker delay: answers held back by the broker's Nagle delay are named with the setting") {
    // mosquitto 2.0.11 without set_tcp_nodelay, measured on loopback
    const std::string line = broker_delay_warning(trips({90, 50, 80}, {59540, 69930, 53850}));
    CHECK(line.find("set_tcp_nodelay true") != std::string::npos);
    CHECK(line.find("59.5 ms") != std::string::npos);  // the median
    CHECK(line.find('\n') == std::string::npos);       // one line
}

TEST_CASE("broker delay: a fast broker gives no warning") {
    // the same broker with set_tcp_nodelay true
    CHECK(broker_delay_warning(trips({250, 40, 90}, {220, 140, 140})).empty());
}

TEST_CASE("broker delay: a far broker is slow both ways and not taken for Nagle") {
    // 30 ms away: a message to itself takes one round trip, a relayed request two
    CHECK(broker_delay_warning(trips({30500, 31000, 30200}, {61000, 62500, 60800})).empty());
}

TEST_CASE("broker delay: one slow relayed sample among fast ones is jitter") {
    CHECK(broker_delay_warning(trips({90, 50, 80}, {300, 90000, 250})).empty());
}

TEST_CASE("broker delay: no measurement gives no warning") { CHECK(broker_delay_warning(BrokerRoundTrip{}).empty()); }
