#include <nclink/transport.hpp>

#include <catch2/catch.hpp>

using nclink::topic_matches;

TEST_CASE("exact topics match only themselves") {
    CHECK(topic_matches("Query/Request/dev1", "Query/Request/dev1"));
    CHECK_FALSE(topic_matches("Query/Request/dev1", "Query/Request/dev2"));
    CHECK_FALSE(topic_matches("Query/Request/dev1", "Query/Request/dev1/app"));
    CHECK_FALSE(topic_matches("Query/Request/dev1/app", "Query/Request/dev1"));
    CHECK_FALSE(topic_matches("", "a"));
    CHECK_FALSE(topic_matches("a", ""));
}

TEST_CASE("+ matches exactly one level, including an empty one") {
    CHECK(topic_matches("Query/Request/dev1/+", "Query/Request/dev1/app7"));
    CHECK_FALSE(topic_matches("Query/Request/dev1/+", "Query/Request/dev1"));
    CHECK_FALSE(topic_matches("Query/Request/dev1/+", "Query/Request/dev1/a/b"));
    CHECK(topic_matches("+/Request/+", "Query/Request/dev1"));
    CHECK(topic_matches("a/+/c", "a//c"));
    CHECK(topic_matches("+", "a"));
    CHECK_FALSE(topic_matches("+", "a/b"));
}

TEST_CASE("# matches the rest, including the parent level") {
    CHECK(topic_matches("Sample/dev1/#", "Sample/dev1/ch1"));
    CHECK(topic_matches("Sample/dev1/#", "Sample/dev1/app/ch1"));
    CHECK(topic_matches("Sample/dev1/#", "Sample/dev1"));
    CHECK(topic_matches("#", "anything/at/all"));
    CHECK_FALSE(topic_matches("Sample/dev1/#", "Sample/dev2/ch1"));
    CHECK_FALSE(topic_matches("Sample/#/x", "Sample/a/x"));  // '#' only last
}

TEST_CASE("wildcards at the start do not match $ topics") {
    CHECK_FALSE(topic_matches("#", "$SYS/broker/uptime"));
    CHECK_FALSE(topic_matches("+/broker/uptime", "$SYS/broker/uptime"));
    CHECK(topic_matches("$SYS/#", "$SYS/broker/uptime"));
}
