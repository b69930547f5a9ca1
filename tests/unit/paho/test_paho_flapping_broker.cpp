// The paho transport (the agent's, the bridge's and the application
// Client's) against a broker that closes each connection soon after its
// CONNACK (support/flapping_broker_check.hpp). The libmosquitto transport's
// twin: tests/unit/transport/test_flapping_broker.cpp.
#include <nclink/paho_transport.hpp>

#include "support/flapping_broker_check.hpp"

using namespace std::chrono_literals;

TEST_CASE("a broker that closes each connection after its CONNACK is retried with a growing back-off") {
    nclink::test::Mqtt5RefusingBroker broker;
    // 50 ms after the CONNACK: paho reports the connection made before it
    // is lost (closed at once, the attempt would look failed to paho).
    broker.close_after_connack(true, 50ms);
    nclink::test::check_backoff_on_flapping_broker(
        broker, [](nclink::MqttOptions o) { return nclink::make_paho_transport(std::move(o)); },
        [](nclink::MqttOptions& o) {
            o.client_id = "paho-flapping";
            o.tcp_nodelay = false;
        });
}
