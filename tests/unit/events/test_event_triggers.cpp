// Triggers of 8.2.27.4 (triggerType a/b/c) and their interplay with the
// filters in one registration (EventWatch), from the standard's wording.
#include "events/event_watch.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::events_detail;

namespace {

std::vector<EventFilter> filters(std::initializer_list<const char*> texts) {
    std::vector<Json> json;
    for (const char* t : texts) json.push_back(Json::parse(t));
    auto parsed = parse_filters(texts.size() == 0 ? std::nullopt : std::optional<std::vector<Json>>(json));
    REQUIRE(parsed.ok());
    return *parsed;
}

// Feeds the values in order; returns the values that made an event.
std::vector<Json> run(EventWatch& watch, std::initializer_list<Json> values) {
    std::vector<Json> fired;
    for (const auto& v : values)
        if (auto f = watch.observe(v)) fired.push_back(f->value);
    return fired;
}

}  // namespace

TEST_CASE("triggers: type names") {
    CHECK(trigger_type_from_string("always") == TriggerType::always);
    CHECK(trigger_type_from_string("normal") == TriggerType::normal);
    CHECK(trigger_type_from_string("Once") == TriggerType::once);
    auto bad = parse_trigger("sometimes");
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::trigger_type);
    CHECK(parse_trigger("").error().code == ErrorCode::trigger_type);
}

TEST_CASE("triggers: TriggerState always fires on every match") {
    TriggerState t(TriggerType::always);
    CHECK(t.fire(true));
    CHECK(t.fire(true));
    CHECK_FALSE(t.fire(false));
    CHECK(t.fire(true));
    CHECK_FALSE(t.finished());
}

TEST_CASE("triggers: TriggerState normal fires only from not matching to matching") {
    TriggerState t(TriggerType::normal);
    CHECK(t.fire(true));  // first match: nothing matched before it
    CHECK_FALSE(t.fire(true));
    CHECK_FALSE(t.fire(false));
    CHECK(t.fire(true));
    CHECK_FALSE(t.fire(true));
}

TEST_CASE("triggers: TriggerState once fires once and finishes") {
    TriggerState t(TriggerType::once);
    CHECK_FALSE(t.fire(false));
    CHECK_FALSE(t.finished());
    CHECK(t.fire(true));
    CHECK(t.finished());
    CHECK_FALSE(t.fire(true));
    CHECK_FALSE(t.fire(false));
}

TEST_CASE("triggers: always fires at registration when the current value matches") {
    EventWatch w(filters({R"({"type":"greater","value":10})"}), TriggerType::always);
    auto first = w.observe(11);
    REQUIRE(first);
    CHECK(first->value == 11);
    CHECK_FALSE(first->old_value);  // nothing before it
}

TEST_CASE("triggers: always fires on every change that still matches") {
    EventWatch w(filters({R"({"type":"greater","value":10})"}), TriggerType::always);
    const auto fired = run(w, {5, 11, 11, 12, 3, 20, 20});
    CHECK(fired == std::vector<Json>{11, 12, 20});  // repeats of the same value are no change
}

TEST_CASE("triggers: always carries the previous value as oldValue") {
    EventWatch w(filters({R"({"type":"change"})"}), TriggerType::always);
    CHECK_FALSE(w.observe(10));  // registration: a change filter has nothing to compare with
    auto e = w.observe(5);
    REQUIRE(e);
    REQUIRE(e->old_value);
    CHECK(*e->old_value == 10);  // the standard's example: oldValue 10, value 5
    CHECK(e->value == 5);
}

TEST_CASE("triggers: normal fires at registration when the current value matches") {
    EventWatch w(filters({R"({"type":"less","value":0})"}), TriggerType::normal);
    CHECK(w.observe(-1));
}

TEST_CASE("triggers: normal fires only when the value enters the filter") {
    EventWatch w(filters({R"({"type":"range","from":10,"to":20})"}), TriggerType::normal);
    const auto fired = run(w, {5, 12, 15, 18, 25, 30, 11, 10, 19});
    CHECK(fired == std::vector<Json>{12, 11, 19});
}

TEST_CASE("triggers: once fires at the first match only") {
    EventWatch w(filters({R"({"type":"equal","value":"ALARM"})"}), TriggerType::once);
    const auto fired = run(w, {"OK", "ALARM", "OK", "ALARM"});
    CHECK(fired == std::vector<Json>{"ALARM"});
    CHECK(w.finished());
}

TEST_CASE("triggers: once fires at registration when the current value matches") {
    EventWatch w(filters({R"({"type":"include","values":[1,2]})"}), TriggerType::once);
    CHECK(w.observe(2));
    CHECK(w.finished());
    CHECK_FALSE(w.observe(1));
}

TEST_CASE("triggers: the default change filter fires on each change") {
    EventWatch w(filters({}), TriggerType::always);
    const auto fired = run(w, {1, 1, 2, 2, "x", nullptr, 1});
    CHECK(fired == std::vector<Json>{2, "x", nullptr, 1});
}

TEST_CASE("triggers: change with variance measures from the last event") {
    EventWatch w(filters({R"({"type":"change","variance":5})"}), TriggerType::always);
    // 100 at registration (no event); 101 is the first event (variance not
    // checked for it); then events only 5 or more away from the last event.
    const auto fired = run(w, {100, 101, 103, 105, 106, 107, 100, 96});
    CHECK(fired == std::vector<Json>{101, 106, 100});
}

TEST_CASE("triggers: normal with variance") {
    EventWatch w(filters({R"({"type":"greater","value":10,"variance":5})"}), TriggerType::normal);
    // 12 enters (first event, recorded 12); 9 leaves; 13 would enter but is
    // only 1 away from 12, so it does not match; 20 matches again.
    const auto fired = run(w, {12, 9, 13, 20});
    CHECK(fired == std::vector<Json>{12, 20});
}

TEST_CASE("triggers: several filters make at most one event per value") {
    EventWatch w(filters({R"({"type":"greater","value":0})", R"({"type":"equal","value":100})"}), TriggerType::always);
    const auto fired = run(w, {100, -1, 5});
    CHECK(fired == std::vector<Json>{100, 5});
}

TEST_CASE("triggers: the standard example range or equal with always") {
    EventWatch w(filters({R"({"type":"range","from":10,"to":20})", R"({"type":"equal","value":100})"}), TriggerType::always);
    const auto fired = run(w, {0, 10, 11, 19, 20, 100, 101, 15});
    CHECK(fired == std::vector<Json>{11, 19, 100, 15});
}
