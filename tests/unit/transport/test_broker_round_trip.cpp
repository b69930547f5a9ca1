// The broker-delay check decides on measured round trips; these inject the
// measurements (no wall-clock), from a broker with and without TCP_NODELAY.
#include <nclink/mqtt_transport.hpp>

#include <catch2/catch.hpp>

using namespace nclink;
using std::chrono::microseconds;

namespace {
BrokerRoundTrip trips(std::vector<long> qos0_us, std::vector<long> qos1_us) {
    BrokerRoundTrip t;
    for (long v : qos0_us) t.qos0.push_back(microseconds(v));
    for (long v : qos1_us) t.qos1.push_back(microseconds(v));
    return t;
}
}  // namespace

TEST_CASE("broker delay: QoS 1 held back by the broker's Nagle delay is named with the setting") {
    const std::string line = broker_delay_warning(trips({400, 380, 520}, {41200, 88000, 40100}));
    CHECK(line.find("set_tcp_nodelay true") != std::string::npos);
    CHECK(line.find("41.2 ms") != std::string::npos);  // the median
    CHECK(line.find('\n') == std::string::npos);       // one line
}

TEST_CASE("broker delay: a fast broker gives no warning") {
    CHECK(broker_delay_warning(trips({400, 380, 520}, {460, 2100, 500})).empty());
}

TEST_CASE("broker delay: a far broker slow at every QoS is not taken for Nagle") {
    CHECK(broker_delay_warning(trips({35000, 36000, 34000}, {36000, 38000, 35500})).empty());
}

TEST_CASE("broker delay: one slow QoS 1 sample among fast ones is jitter") {
    CHECK(broker_delay_warning(trips({400, 380, 520}, {460, 90000, 500})).empty());
}

TEST_CASE("broker delay: no measurement gives no warning") { CHECK(broker_delay_warning(BrokerRoundTrip{}).empty()); }
