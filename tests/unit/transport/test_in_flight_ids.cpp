// The publishes libmosquitto has not yet confirmed (transport/in_flight_ids.hpp).
#include "transport/in_flight_ids.hpp"

#include <catch2/catch.hpp>

using nclink::transport_detail::InFlightIds;

TEST_CASE("a confirmation finds the attempt its message id was recorded for, once") {
    InFlightIds ids(4);
    CHECK_FALSE(ids.record(7, 100));
    CHECK_FALSE(ids.record(8, 101));
    CHECK_FALSE(ids.record(9, 102));
    CHECK(ids.confirm(8) == 101u);
    CHECK(ids.confirm(7) == 100u);
    CHECK(ids.size() == 1);
    CHECK(ids.confirm(9) == 102u);
    CHECK(ids.size() == 0);
}

TEST_CASE("a confirmation that comes before the sender recorded the id is kept for it") {
    InFlightIds ids(4);
    CHECK_FALSE(ids.confirm(5));  // on_publish before mosquitto_publish() returned 5
    CHECK(ids.early() == 1);
    CHECK(ids.record(5, 42));  // delivered at once, nothing left waiting
    CHECK(ids.size() == 0);
    CHECK(ids.early() == 0);
    CHECK_FALSE(ids.record(5, 43));  // the id used again later is a new message
    CHECK(ids.confirm(5) == 43u);
}

TEST_CASE("a lost connection forgets what it took") {
    InFlightIds ids(2);
    (void)ids.record(1, 1);
    (void)ids.confirm(2);
    ids.clear();
    CHECK(ids.size() == 0);
    CHECK(ids.early() == 0);
    CHECK_FALSE(ids.confirm(1));  // not answered twice
}

TEST_CASE("more messages than reserved still work") {
    InFlightIds ids(2);
    for (int mid = 1; mid <= 100; ++mid) CHECK_FALSE(ids.record(mid, static_cast<std::uint64_t>(mid) * 10));
    for (int mid = 100; mid >= 1; --mid) CHECK(ids.confirm(mid) == static_cast<std::uint64_t>(mid) * 10);
    CHECK(ids.size() == 0);
}
