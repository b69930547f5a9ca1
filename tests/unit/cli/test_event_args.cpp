// `nclink events` argument parsing (tools/nclink/event_args.hpp, header-only).
#include "event_args.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::cli;

namespace {

Json one(const std::string& spec) {
    const auto filters = parse_filter_arg(spec);
    REQUIRE(filters.size() == 1);
    return filters[0];
}

}  // namespace

TEST_CASE("event args: short filter forms") {
    CHECK(one("change") == Json{{"type", "change"}});
    CHECK(one("change:2.5") == Json{{"type", "change"}, {"variance", 2.5}});
    CHECK(one("equal:100") == Json{{"type", "equal"}, {"value", 100}});
    CHECK(one("equal:true") == Json{{"type", "equal"}, {"value", true}});
    CHECK(one("equal:alarm") == Json{{"type", "equal"}, {"value", "alarm"}});
    CHECK(one("equal:a,b") == Json{{"type", "equal"}, {"value", "a,b"}});
    CHECK(one("range:10,20") == Json{{"type", "range"}, {"from", 10}, {"to", 20}});
    CHECK(one("range:-1.5,2,0.5") == Json{{"type", "range"}, {"from", -1.5}, {"to", 2}, {"variance", 0.5}});
    CHECK(one("less:5") == Json{{"type", "less"}, {"value", 5}});
    CHECK(one("greater:8000,100") == Json{{"type", "greater"}, {"value", 8000}, {"variance", 100}});
    CHECK(one("include:1,run,false") == Json{{"type", "include"}, {"values", {1, "run", false}}});
}

TEST_CASE("event args: JSON filters pass through for the adapter to check") {
    CHECK(one(R"({"type":"change","from":1})") == Json{{"type", "change"}, {"from", 1}});
    const auto two = parse_filter_arg(R"([{"type":"range","from":10,"to":20},{"type":"equal","value":100}])");
    REQUIRE(two.size() == 2);
    CHECK(two[1]["value"] == 100);
}

TEST_CASE("event args: malformed short forms are usage errors") {
    CHECK_THROWS_AS(parse_filter_arg(""), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("bogus:1"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("range:10"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("range:a,b"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("less"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("less:1,2,3"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("equal"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("include"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("{not json"), UsageError);
    CHECK_THROWS_AS(parse_filter_arg("[1"), UsageError);
}

TEST_CASE("event args: one line per event") {
    EventData e;
    e.id = "event_1";
    e.event.id = "tools";
    e.event.index = 3;
    e.event.old_value = Json{{"id", "T1"}};
    e.event.value = Json{{"id", "T2"}};
    CHECK(format_event(e) == R"(event_1 tools[3] {"id":"T1"} -> {"id":"T2"})");
    EventData first;
    first.id = "event_2";
    first.event.id = "params";
    first.event.key = "P1";
    first.event.value = 5;
    CHECK(format_event(first) == "event_2 params[P1] 5");
}
