#include "core/nearest.hpp"

#include <catch2/catch.hpp>

using nclink::core_detail::edit_distance;
using nclink::core_detail::nearest_name;

TEST_CASE("edit distance counts swaps of neighbours as one, ignoring case") {
    CHECK(edit_distance("uri", "url") == 1);
    CHECK(edit_distance("modle", "model") == 1);
    CHECK(edit_distance("SPINDLE_SPED", "spindle_speed") == 1);
    CHECK(edit_distance("", "abc") == 3);
}

TEST_CASE("the nearest name is suggested only when it is a likely typo") {
    const std::vector<std::string_view> keys{"url", "client_id", "username", "password", "keep_alive_s"};
    CHECK(nearest_name("uri", keys) == "url");
    CHECK(nearest_name("user_name", keys) == "username");
    CHECK(nearest_name("keep_alive", keys) == "keep_alive_s");
    CHECK(nearest_name("URL", keys) == "url");
    CHECK_FALSE(nearest_name("qos", keys));
    CHECK_FALSE(nearest_name("", keys));
}
