// The client's liveness bookkeeping and its de-duplication of QoS 1 repeats
// (src/client/keep_alive.hpp, src/client/duplicate_filter.hpp).
#include "client/duplicate_filter.hpp"
#include "client/keep_alive.hpp"

#include <catch2/catch.hpp>

using nclink::client_detail::DuplicateFilter;
using nclink::client_detail::KeepAlive;
using namespace std::chrono_literals;

TEST_CASE("keep-alive: a device with a registration is due every interval, with one registered item") {
    KeepAlive k(100ms);
    const auto t0 = KeepAlive::Clock::time_point{} + 1h;
    CHECK_FALSE(k.next_due());
    k.hold("mill", "event:e1", "x_position", t0);
    k.hold("mill", "sample:dyn1", "spindle_speed", t0 + 50ms);  // the device keeps its schedule
    REQUIRE(k.next_due());
    CHECK(*k.next_due() == t0 + 100ms);
    CHECK(k.due(t0 + 99ms).empty());
    const auto due = k.due(t0 + 100ms);
    REQUIRE(due.size() == 1);
    CHECK(due[0].first == "mill");
    CHECK((due[0].second == "x_position" || due[0].second == "spindle_speed"));
    CHECK(*k.next_due() == t0 + 200ms);
    CHECK(k.due(t0 + 150ms).empty());
}

TEST_CASE("keep-alive: released registrations stop it, a reconnect makes every device due") {
    KeepAlive k(100ms);
    const auto t0 = KeepAlive::Clock::time_point{} + 1h;
    k.hold("a", "event:1", "x", t0);
    k.hold("b", "event:2", "y", t0);
    k.release("a", "event:1");
    CHECK(k.devices() == 1);
    k.all_due(t0 + 10ms);
    const auto due = k.due(t0 + 10ms);
    REQUIRE(due.size() == 1);
    CHECK(due[0].first == "b");
    k.release("b", "event:2");
    CHECK_FALSE(k.next_due());
    CHECK(k.due(t0 + 1h).empty());
}

TEST_CASE("keep-alive: interval 0 keeps nothing") {
    KeepAlive k(0ms);
    k.hold("a", "event:1", "x", KeepAlive::Clock::now());
    CHECK(k.devices() == 0);
    CHECK_FALSE(k.next_due());
}

TEST_CASE("duplicate filter: each key once per stream, out of order too, within its memory") {
    DuplicateFilter f(3);
    CHECK(f.first("Sample/m/ch", "100"));
    CHECK(f.first("Sample/m/ch", "300"));
    CHECK(f.first("Sample/m/ch", "200"));  // a replayed DTU arrives after newer ones
    CHECK_FALSE(f.first("Sample/m/ch", "100"));
    CHECK(f.first("Sample/m/other", "100"));  // streams are apart
    CHECK(f.first("Sample/m/ch", "400"));     // forgets the oldest remembered
    CHECK(f.first("Sample/m/ch", "100"));
    DuplicateFilter off(0);
    CHECK(off.first("s", "k"));
    CHECK(off.first("s", "k"));
}
