// Wall-clock milliseconds as ISO 8601 text without time_t (log lines): the
// dates a 32-bit time_t cannot hold (Debian 12 armhf, after 2038-01-19)
// print as they are, and so do the calendar's edges.
#include "core/utc_time.hpp"

#include <catch2/catch.hpp>

using nclink::core_detail::utc_iso8601_ms;

TEST_CASE("utc text: the epoch, milliseconds and times before it") {
    CHECK(utc_iso8601_ms(0) == "1970-01-01T00:00:00.000Z");
    CHECK(utc_iso8601_ms(1) == "1970-01-01T00:00:00.001Z");
    CHECK(utc_iso8601_ms(-1) == "1969-12-31T23:59:59.999Z");
    CHECK(utc_iso8601_ms(-1001) == "1969-12-31T23:59:58.999Z");
    CHECK(utc_iso8601_ms(-86'400'000) == "1969-12-31T00:00:00.000Z");
    CHECK(utc_iso8601_ms(-2'208'988'800'000) == "1900-01-01T00:00:00.000Z");
    CHECK(utc_iso8601_ms(1'700'000'000'000) == "2023-11-14T22:13:20.000Z");
}

TEST_CASE("utc text: past the 32-bit time_t (2038-01-19T03:14:07Z) the date stays right") {
    CHECK(utc_iso8601_ms(2'147'483'647'000) == "2038-01-19T03:14:07.000Z");
    CHECK(utc_iso8601_ms(2'147'483'648'000) == "2038-01-19T03:14:08.000Z");  // 1901-12-13 through a 32-bit time_t
    CHECK(utc_iso8601_ms(4'102'444'800'000) == "2100-01-01T00:00:00.000Z");
    CHECK(utc_iso8601_ms(253'402'300'799'999) == "9999-12-31T23:59:59.999Z");
}

TEST_CASE("utc text: leap days, and the century years that are not leap years") {
    CHECK(utc_iso8601_ms(951'782'400'000) == "2000-02-29T00:00:00.000Z");
    CHECK(utc_iso8601_ms(951'868'799'999) == "2000-02-29T23:59:59.999Z");
    CHECK(utc_iso8601_ms(951'868'800'000) == "2000-03-01T00:00:00.000Z");
    CHECK(utc_iso8601_ms(4'107'456'000'000) == "2100-02-28T00:00:00.000Z");
    CHECK(utc_iso8601_ms(4'107'542'400'000) == "2100-03-01T00:00:00.000Z");  // no 2100-02-29
    CHECK(utc_iso8601_ms(13'574'563'200'000) == "2400-02-29T00:00:00.000Z");
    CHECK(utc_iso8601_ms(1'709'164'800'000) == "2024-02-29T00:00:00.000Z");
    CHECK(utc_iso8601_ms(1'735'689'599'999) == "2024-12-31T23:59:59.999Z");
}
