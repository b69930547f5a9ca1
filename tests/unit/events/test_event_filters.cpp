// Filters of 8.2.27.4 / figure 16, case by case from the standard's wording.
#include "events/event_filter.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::events_detail;

namespace {

EventFilter filter(const char* text) {
    auto parsed = parse_filter(Json::parse(text));
    INFO(text << ": " << (parsed ? std::string() : parsed.error().describe()));
    REQUIRE(parsed.ok());
    return *parsed;
}

ErrorCode refusal(const char* text) {
    auto parsed = parse_filter(Json::parse(text));
    INFO(text);
    REQUIRE_FALSE(parsed.ok());
    return parsed.error().code;
}

bool holds(const EventFilter& f, const Json& value, const Json* previous = nullptr) {
    return condition_holds(f, value, previous);
}

}  // namespace

TEST_CASE("filters: no filters means one change filter") {
    auto none = parse_filters(std::nullopt);
    REQUIRE(none.ok());
    REQUIRE(none->size() == 1);
    CHECK(none->front().type == FilterType::change);
    auto empty = parse_filters(std::vector<Json>{});
    REQUIRE(empty.ok());
    REQUIRE(empty->size() == 1);
    CHECK(empty->front().type == FilterType::change);
}

TEST_CASE("filters: change holds when the value differs from the previous one") {
    const auto f = filter(R"({"type":"change"})");
    const Json five = 5, six = 6, five_f = 5.0, text = "a";
    CHECK_FALSE(holds(f, 5));  // no previous value (registration): nothing changed
    CHECK_FALSE(holds(f, 5, &five));
    CHECK_FALSE(holds(f, 5, &five_f));  // 5 and 5.0 are the same number
    CHECK(holds(f, 5, &six));
    CHECK(holds(f, "b", &text));
    CHECK(holds(f, nullptr, &five));  // a value that became unknown is a change too
}

TEST_CASE("filters: equal takes a number a string or a boolean") {
    const auto n = filter(R"({"type":"equal","value":100})");
    CHECK(holds(n, 100));
    CHECK(holds(n, 100.0));
    CHECK_FALSE(holds(n, 100.5));
    CHECK_FALSE(holds(n, "100"));  // no type juggling
    const auto s = filter(R"({"type":"equal","value":"RUN"})");
    CHECK(holds(s, "RUN"));
    CHECK_FALSE(holds(s, "run"));
    const auto b = filter(R"({"type":"equal","value":true})");
    CHECK(holds(b, true));
    CHECK_FALSE(holds(b, false));
    CHECK_FALSE(holds(b, 1));
}

TEST_CASE("filters: range excludes both bounds") {
    const auto f = filter(R"({"type":"range","from":10,"to":20})");
    CHECK_FALSE(holds(f, 10));  // "不包含此值"
    CHECK(holds(f, 10.001));
    CHECK(holds(f, 15));
    CHECK(holds(f, 19.999));
    CHECK_FALSE(holds(f, 20));
    CHECK_FALSE(holds(f, 9));
    CHECK_FALSE(holds(f, 21));
    CHECK_FALSE(holds(f, "15"));
    CHECK_FALSE(holds(f, nullptr));
    const auto empty = filter(R"({"type":"range","from":20,"to":10})");
    CHECK_FALSE(holds(empty, 15));  // an empty range is accepted and never holds
}

TEST_CASE("filters: less and greater are strict comparisons with a number") {
    const auto less = filter(R"({"type":"less","value":5})");
    CHECK(holds(less, 4.99));
    CHECK_FALSE(holds(less, 5));
    CHECK_FALSE(holds(less, 6));
    CHECK_FALSE(holds(less, true));
    const auto greater = filter(R"({"type":"greater","value":-1.5})");
    CHECK(holds(greater, 0));
    CHECK_FALSE(holds(greater, -1.5));
    CHECK_FALSE(holds(greater, -2));
    CHECK_FALSE(holds(greater, "0"));
}

TEST_CASE("filters: include holds for a value in the values array") {
    const auto f = filter(R"({"type":"include","values":[1,2,34,5,"idle",false]})");
    CHECK(holds(f, 34));
    CHECK(holds(f, 2.0));
    CHECK(holds(f, "idle"));
    CHECK(holds(f, false));
    CHECK_FALSE(holds(f, 3));
    CHECK_FALSE(holds(f, "IDLE"));
    CHECK_FALSE(holds(f, true));
    const auto none = filter(R"({"type":"include","values":[]})");
    CHECK_FALSE(holds(none, 1));
}

TEST_CASE("filters: variance compares with the value recorded at the previous event") {
    const auto f = filter(R"({"type":"greater","value":10,"variance":2})");
    const Json recorded = 12;
    CHECK(filter_matches(f, 13, nullptr, nullptr));          // first event: variance not checked
    CHECK_FALSE(filter_matches(f, 13, nullptr, &recorded));  // |13-12| < 2
    CHECK(filter_matches(f, 14, nullptr, &recorded));        // |14-12| >= 2 (equality counts)
    CHECK(filter_matches(f, 10.5 + 20, nullptr, &recorded));
    const Json low = 30;
    CHECK(filter_matches(f, 28, nullptr, &low));       // the change may go either way
    CHECK_FALSE(filter_matches(f, 9, nullptr, &low));  // the condition itself still has to hold
}

TEST_CASE("filters: variance on change range less and greater only") {
    CHECK(filter(R"({"type":"change","variance":0.5})").variance == Approx(0.5));
    CHECK(filter(R"({"type":"range","from":0,"to":1,"variance":1})").variance == Approx(1));
    CHECK(filter(R"({"type":"less","value":0,"variance":1})").variance);
    CHECK(filter(R"({"type":"greater","value":0,"variance":1})").variance);
    CHECK(refusal(R"({"type":"equal","value":1,"variance":1})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"include","values":[1],"variance":1})") == ErrorCode::filter_arguments_mismatch);
}

TEST_CASE("filters: variance only measures numbers") {
    const auto f = filter(R"({"type":"change","variance":3})");
    const Json text = "a";
    const Json number = 1;
    CHECK(variance_holds(f, "b", &text));
    CHECK(variance_holds(f, "b", &number));
    CHECK_FALSE(variance_holds(f, 2, &number));
    CHECK(variance_holds(f, 4, &number));
}

TEST_CASE("filters: unknown or missing type is 419") {
    CHECK(refusal(R"({"type":"between","from":1,"to":2})") == ErrorCode::filter_type);
    CHECK(refusal(R"({"from":1,"to":2})") == ErrorCode::filter_type);
    CHECK(refusal(R"({"type":3})") == ErrorCode::filter_type);
    CHECK(refusal(R"("change")") == ErrorCode::filter_type);
}

TEST_CASE("filters: type names are case-insensitive") {
    CHECK(filter(R"({"type":"Range","from":1,"to":2})").type == FilterType::range);
    CHECK(filter(R"({"type":"EQUAL","value":1})").type == FilterType::equal);
}

TEST_CASE("filters: arguments that do not fit the type are 421") {
    // The standard's own example: a change filter with "from".
    CHECK(refusal(R"({"type":"change","from":1})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"equal"})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"equal","value":[1]})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"equal","value":null})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"equal","values":[1]})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"range","from":1})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"range","to":1})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"range","from":"1","to":2})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"range","from":1,"to":2,"value":3})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"less","value":"5"})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"less"})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"greater","value":true})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"greater","value":1,"to":2})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"include","values":1})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"include"})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"include","values":[1,[2]]})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"include","values":[{"a":1}]})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"change","variance":-1})") == ErrorCode::filter_arguments_mismatch);
    CHECK(refusal(R"({"type":"change","variance":"2"})") == ErrorCode::filter_arguments_mismatch);
}

TEST_CASE("filters: several filters are OR-ed in order") {
    // The standard's example: in (10, 20) or equal to 100.
    auto filters = parse_filters(
        std::vector<Json>{Json::parse(R"({"type":"range","from":10,"to":20})"), Json::parse(R"({"type":"equal","value":100})")});
    REQUIRE(filters.ok());
    CHECK(first_match(*filters, 15, nullptr, nullptr) == std::optional<std::size_t>(0));
    CHECK(first_match(*filters, 100, nullptr, nullptr) == std::optional<std::size_t>(1));
    CHECK_FALSE(first_match(*filters, 50, nullptr, nullptr));
    CHECK_FALSE(first_match(*filters, 20, nullptr, nullptr));
}

TEST_CASE("filters: the first bad filter decides the error") {
    auto bad = parse_filters(std::vector<Json>{Json::parse(R"({"type":"equal","value":1})"), Json::parse(R"({"type":"nope"})"),
                                               Json::parse(R"({"type":"change","from":1})")});
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::filter_type);
}
