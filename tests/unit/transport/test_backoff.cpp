#include "transport/backoff.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace nclink::transport_detail;
using namespace std::chrono_literals;

TEST_CASE("reconnect waits are jittered over the second half of the back-off") {
    std::mt19937 rng(7);
    std::set<long> seen;
    for (int i = 0; i < 200; ++i) {
        const auto wait = jittered(1000ms, rng);
        CHECK(wait >= 500ms);
        CHECK(wait <= 1000ms);
        seen.insert(static_cast<long>(wait.count()));
    }
    // Terminals dropped together do not retry together.
    CHECK(seen.size() > 100);
    CHECK(jittered(1ms, rng) == 1ms);
    CHECK(jittered(0ms, rng) == 0ms);
}

namespace {
const ReconnectBackoff::Clock::time_point t0{std::chrono::hours(1)};
}

TEST_CASE("the back-off doubles per failed attempt up to its cap") {
    ReconnectBackoff b(50ms, 800ms);
    CHECK(b.delay() == 50ms);
    for (auto expected : {100ms, 200ms, 400ms, 800ms, 800ms}) {
        b.failed();
        CHECK(b.delay() == expected);
    }
}

TEST_CASE("a connection dropped right after its CONNACK does not reset the back-off: it doubles it") {
    ReconnectBackoff b(50ms, 800ms);
    // Accepted, then closed at once, over and over (a RabbitMQ node that
    // CONNACKs and closes, a broker that kicks the session at SUBSCRIBE).
    auto now = t0;
    for (auto expected : {100ms, 200ms, 400ms, 800ms, 800ms, 800ms}) {
        b.connected(now);
        now += 5ms;
        CHECK_FALSE(b.lost(now));
        CHECK(b.delay() == expected);
        now += b.delay();
    }
}

TEST_CASE("only a connection that stayed up as long as the back-off cap starts it again from the minimum") {
    ReconnectBackoff b(50ms, 800ms);
    CHECK(b.stable_period() == 800ms);
    for (int i = 0; i < 4; ++i) b.failed();
    REQUIRE(b.delay() == 800ms);

    b.connected(t0);
    CHECK_FALSE(b.lost(t0 + 799ms));  // just short of stable: still a failed attempt
    CHECK(b.delay() == 800ms);
    CHECK(b.lasted(t0 + 799ms) == 799ms);

    b.connected(t0 + 2s);
    CHECK(b.lost(t0 + 2s + 800ms));  // stable
    CHECK(b.delay() == 50ms);

    // A reset does not stick: the next quick loss doubles again.
    b.connected(t0 + 10s);
    CHECK_FALSE(b.lost(t0 + 10s + 1ms));
    CHECK(b.delay() == 100ms);
}

TEST_CASE("a long back-off cap asks for at most a minute of connection to count as stable") {
    CHECK(stable_after(10s) == 10s);
    CHECK(stable_after(std::chrono::minutes(5)) == 60s);
    ReconnectBackoff b(250ms, std::chrono::minutes(5));
    for (int i = 0; i < 20; ++i) b.failed();
    REQUIRE(b.delay() == std::chrono::minutes(5));
    b.connected(t0);
    CHECK(b.lost(t0 + 60s));
    CHECK(b.delay() == 250ms);
}

TEST_CASE("the wait before an attempt is the back-off jittered") {
    std::mt19937 rng(3);
    ReconnectBackoff b(400ms, 10s);
    for (int i = 0; i < 50; ++i) {
        const auto w = b.wait(rng);
        CHECK(w >= 200ms);
        CHECK(w <= 400ms);
    }
}
