// The failover list of a transport (src/transport/broker_list.hpp): entries
// written out as URLs, the checks with the words a user sees, and the
// rotation the transports follow.
#include "transport/broker_list.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::transport_detail;

TEST_CASE("failover list: a host:port entry takes the scheme of the url, a URL stays as given") {
    CHECK(failover_entry_url("b.plant:1884", "tcp://a.plant:1883") == "tcp://b.plant:1884");
    CHECK(failover_entry_url("b.plant:8884", "ssl://a.plant:8883") == "ssl://b.plant:8884");
    CHECK(failover_entry_url("b.plant", "mqtts://a.plant") == "mqtts://b.plant");
    CHECK(failover_entry_url("mqtt://b.plant:1884", "tcp://a.plant:1883") == "mqtt://b.plant:1884");

    auto list = broker_list("tcp://a.plant:1883", {"b.plant:1884", "mqtt://c.plant", "[::1]:1885"});
    REQUIRE(list);
    REQUIRE(list->size() == 4);
    CHECK((*list)[0].url == "tcp://a.plant:1883");
    CHECK((*list)[1].url == "tcp://b.plant:1884");
    CHECK((*list)[1].host == "b.plant");
    CHECK((*list)[1].port == 1884);
    CHECK((*list)[2].url == "mqtt://c.plant");
    CHECK((*list)[2].port == 1883);  // the scheme's default
    CHECK((*list)[3].host == "::1");
    CHECK((*list)[3].port == 1885);
}

TEST_CASE("failover list: a bad entry is an error naming it and saying what is wrong") {
    auto bad_port = broker_list("tcp://a:1883", {"b:1884", "c:port"});
    REQUIRE_FALSE(bad_port);
    CHECK(bad_port.error().code == ErrorCode::value_type);
    CHECK_THAT(bad_port.error().message, Catch::StartsWith("failover entry 1 'c:port': unusable broker URL 'tcp://c:port'"));

    auto scheme = broker_list("tcp://a:1883", {"http://b:80"});
    REQUIRE_FALSE(scheme);
    CHECK_THAT(scheme.error().message, Catch::Contains("unknown scheme 'http'"));

    auto empty = broker_list("tcp://a:1883", {""});
    REQUIRE_FALSE(empty);
    CHECK_THAT(empty.error().message, Catch::StartsWith("failover entry 0 '': unusable broker URL"));

    // TLS and credentials are the same for every broker of the list.
    auto plain_after_tls = broker_list("ssl://a:8883", {"tcp://b:1883"});
    REQUIRE_FALSE(plain_after_tls);
    CHECK_THAT(plain_after_tls.error().message, Catch::Contains("'tcp://b:1883' does not use TLS and url 'ssl://a:8883' does"));
    auto tls_after_plain = broker_list("tcp://a:1883", {"mqtts://b:8883"});
    REQUIRE_FALSE(tls_after_plain);
    CHECK_THAT(tls_after_plain.error().message, Catch::Contains("'mqtts://b:8883' uses TLS and url 'tcp://a:1883' does not"));
    CHECK(broker_list("ssl://a:8883", {"mqtts://b:8883", "wss://c/mqtt", "d:8884"}));

    // A broker named twice (host case and scheme spelling aside).
    auto again = broker_list("tcp://a:1883", {"A:1883"});
    REQUIRE_FALSE(again);
    CHECK_THAT(again.error().message, Catch::Contains("names the broker of url 'tcp://a:1883' again"));
    auto twice = broker_list("tcp://a:1883", {"b:1884", "mqtt://b:1884"});
    REQUIRE_FALSE(twice);
    CHECK_THAT(twice.error().message, Catch::Contains("failover entry 1 'mqtt://b:1884': 'mqtt://b:1884' names the broker of "
                                                      "failover entry 0 ('b:1884') again"));
    CHECK(broker_list("tcp://a:1883", {"a:1884"}));  // same host, another port: another broker

    // The url itself is checked as check_broker_url() does.
    auto primary = broker_list("a:1883", {});
    REQUIRE_FALSE(primary);
    CHECK_THAT(primary.error().message, Catch::Contains("it has no scheme"));
}

TEST_CASE("failover list: the rotation goes through the list in order and wraps around") {
    BrokerRotation rotation(broker_list("tcp://a:1", {"b:2", "c:3"}).value());
    CHECK(rotation.size() == 3);
    CHECK(rotation.current().url == "tcp://a:1");
    std::vector<std::string> seen;
    for (int i = 0; i < 4; ++i) {
        CHECK(rotation.advance());
        seen.push_back(rotation.current().url);
    }
    CHECK(seen == std::vector<std::string>{"tcp://b:2", "tcp://c:3", "tcp://a:1", "tcp://b:2"});

    BrokerRotation single(broker_list("tcp://a:1", {}).value());
    CHECK_FALSE(single.advance());
    CHECK(single.current().url == "tcp://a:1");
}
