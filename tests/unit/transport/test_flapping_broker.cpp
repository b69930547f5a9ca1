// The libmosquitto transport against a broker that closes each connection
// right after its CONNACK (support/flapping_broker_check.hpp). The paho
// transport's twin: tests/unit/paho/test_paho_flapping_broker.cpp.
#include <nclink/mqtt_transport.hpp>

#include "support/flapping_broker_check.hpp"

using namespace std::chrono_literals;

TEST_CASE("a broker that closes each connection after its CONNACK is retried with a growing back-off") {
    nclink::test::Mqtt5RefusingBroker broker;
    broker.close_after_connack(true);
    nclink::test::check_backoff_on_flapping_broker(
        broker, [](nclink::MqttOptions o) { return nclink::make_mqtt_transport(std::move(o)); },
        [](nclink::MqttOptions& o) { o.client_id = "flapping"; });
}
