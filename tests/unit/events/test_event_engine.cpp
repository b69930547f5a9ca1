// EventEngine: registrations, ownership, capacity, activation and release,
// without threads.
#include "events/event_engine.hpp"
#include "events/value_inbox.hpp"

#include <catch2/catch.hpp>

#include <limits>

using namespace nclink;
using namespace nclink::events_detail;

namespace {

EventSpec spec(const char* item, const char* filters_json = nullptr, TriggerType trigger = TriggerType::always) {
    EventSpec s;
    s.item = item;
    std::optional<std::vector<Json>> filters;
    if (filters_json) filters = Json::parse(filters_json).get<std::vector<Json>>();
    s.filters = *parse_filters(filters);
    s.trigger = trigger;
    return s;
}

const std::optional<std::string> kApp = std::string("app");
const std::optional<std::string> kOther = std::string("other");

}  // namespace

TEST_CASE("engine: capacity is max_events and a full engine answers 416") {
    EventEngine engine(2, "t");
    REQUIRE(engine.add(kApp, spec("a")).ok());
    REQUIRE(engine.add(kOther, spec("b")).ok());
    auto third = engine.add(kApp, spec("c"));
    REQUIRE_FALSE(third.ok());
    CHECK(third.error().code == ErrorCode::insufficient_event);
    EventEngine none(0, "t");
    CHECK(none.add(kApp, spec("a")).error().code == ErrorCode::insufficient_event);
}

TEST_CASE("engine: event ids are unique and carry the prefix") {
    EventEngine engine(8, "abc");
    auto a = engine.add(kApp, spec("a"));
    auto b = engine.add(kApp, spec("a"));
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(*a != *b);
    CHECK(a->find("abc") != std::string::npos);
}

TEST_CASE("engine: remove checks the owner") {
    EventEngine engine(4, "t");
    const auto id = *engine.add(kApp, spec("a"));
    CHECK(engine.remove("event_nope", kApp).error().code == ErrorCode::node_not_exists);
    CHECK(engine.remove(id, kOther).error().code == ErrorCode::permission_denied);
    CHECK(engine.remove(id, std::nullopt).error().code == ErrorCode::permission_denied);
    CHECK(engine.remove(id, kApp).ok());
    CHECK(engine.remove(id, kApp).error().code == ErrorCode::node_not_exists);
    CHECK(engine.released() == 1);
    CHECK(engine.add(kApp, spec("a")).ok());  // the slot is free again
}

TEST_CASE("engine: remove_owner releases only that application's events") {
    EventEngine engine(4, "t");
    (void)engine.add(kApp, spec("a"));
    (void)engine.add(kApp, spec("b"));
    const auto kept = *engine.add(kOther, spec("a"));
    CHECK(engine.remove_owner("app").size() == 2);
    CHECK(engine.size() == 1);
    CHECK(engine.contains(kept));
    CHECK(engine.released() == 2);
}

TEST_CASE("engine: values before activation are not seen") {
    EventEngine engine(4, "t");
    const auto id = *engine.add(kApp, spec("a", R"([{"type":"greater","value":0}])"));
    CHECK(engine.observe("a", 5, 1).empty());
    CHECK(engine.active_items().empty());
    auto fired = engine.activate(id, Json(1), 2);  // matches at registration
    REQUIRE(fired.size() == 1);
    CHECK(fired[0].dtu.id == id);
    CHECK(fired[0].dtu.time == 2);
    CHECK(fired[0].dtu.event.id == "a");
    CHECK(fired[0].dtu.event.value == 1);
    CHECK_FALSE(fired[0].dtu.event.old_value);
    CHECK(fired[0].owner == kApp);
    CHECK(engine.active_items().count("a") == 1);
}

TEST_CASE("engine: activation without a value waits for the first observation") {
    EventEngine engine(4, "t");
    const auto id = *engine.add(kApp, spec("a", R"([{"type":"greater","value":0}])"));
    CHECK(engine.activate(id, std::nullopt, 1).empty());
    auto fired = engine.observe("a", 3, 5);
    REQUIRE(fired.size() == 1);
    CHECK_FALSE(fired[0].dtu.event.old_value);
}

TEST_CASE("engine: observe evaluates every registration of the item") {
    EventEngine engine(4, "t");
    const auto a = *engine.add(kApp, spec("x"));
    const auto b = *engine.add(kOther, spec("x", R"([{"type":"less","value":0}])"));
    const auto c = *engine.add(kApp, spec("y"));
    (void)engine.activate(a, Json(1), 0);
    (void)engine.activate(b, Json(1), 0);
    (void)engine.activate(c, Json(1), 0);
    auto fired = engine.observe("x", -5, 10);
    REQUIRE(fired.size() == 2);
    CHECK(engine.fired() == 2);
    for (const auto& f : fired) {
        REQUIRE(f.dtu.event.old_value);
        CHECK(*f.dtu.event.old_value == 1);
        CHECK(f.dtu.event.value == -5);
    }
}

TEST_CASE("engine: a once event is released after it fired") {
    EventEngine engine(1, "t");
    const auto id = *engine.add(kApp, spec("x", R"([{"type":"equal","value":3}])", TriggerType::once));
    CHECK(engine.activate(id, Json(1), 0).empty());
    CHECK(engine.observe("x", 3, 1).size() == 1);
    CHECK_FALSE(engine.contains(id));
    CHECK(engine.released() == 1);
    CHECK(engine.observe("x", 4, 2).empty());
    CHECK(engine.observe("x", 3, 3).empty());
    CHECK(engine.add(kApp, spec("x")).ok());  // resource freed
}

TEST_CASE("engine: a once event matching at registration is released at once") {
    EventEngine engine(1, "t");
    const auto id = *engine.add(kApp, spec("x", R"([{"type":"equal","value":3}])", TriggerType::once));
    CHECK(engine.activate(id, Json(3), 0).size() == 1);
    CHECK(engine.size() == 0);
}

TEST_CASE("engine: dict and list elements carry key and index") {
    EventEngine engine(4, "t");
    auto dict = spec("params");
    dict.kind = DataKind::dict;
    dict.key = "p1";
    auto list = spec("tools");
    list.kind = DataKind::list;
    list.index = 1;
    const auto d = *engine.add(kApp, dict);
    const auto l = *engine.add(kApp, list);
    (void)engine.activate(d, Json{{"p1", 1}, {"p2", 1}}, 0);
    (void)engine.activate(l, Json::array({"a", "b"}), 0);
    CHECK(engine.observe("params", Json{{"p1", 1}, {"p2", 2}}, 1).empty());  // another key changed
    auto fd = engine.observe("params", Json{{"p1", 2}, {"p2", 2}}, 2);
    REQUIRE(fd.size() == 1);
    CHECK(fd[0].dtu.event.key == std::optional<std::string>("p1"));
    CHECK_FALSE(fd[0].dtu.event.index);
    CHECK(fd[0].dtu.event.value == 2);
    CHECK(engine.observe("params", Json{{"p2", 2}}, 3).empty());  // key gone: nothing to compare
    CHECK(engine.observe("tools", Json::array({"z", "b"}), 4).empty());
    auto fl = engine.observe("tools", Json::array({"z", "c"}), 5);
    REQUIRE(fl.size() == 1);
    CHECK(fl[0].dtu.event.index == std::optional<std::int64_t>(1));
    CHECK(*fl[0].dtu.event.old_value == "b");
    CHECK(engine.observe("tools", Json::array({"z"}), 6).empty());  // index out of range now
}

TEST_CASE("engine: retain_items releases events of items a new model lost") {
    EventEngine engine(4, "t");
    (void)engine.add(kApp, spec("gone"));
    const auto kept = *engine.add(kApp, spec("kept"));
    const auto released = engine.retain_items([](const EventSpec& s) { return s.item == "kept"; });
    CHECK(released.size() == 1);
    CHECK(engine.contains(kept));
    CHECK(engine.watched_items() == std::set<std::string>{"kept"});
}

TEST_CASE("engine: the Event DTU encodes per 8.2.31") {
    EventEngine engine(1, "t");
    auto s = spec("tools");
    s.kind = DataKind::list;
    s.index = 0;
    const auto id = *engine.add(kApp, s);
    (void)engine.activate(id, Json::array({10}), 0);
    auto fired = engine.observe("tools", Json::array({5}), 19202912);
    REQUIRE(fired.size() == 1);
    fired[0].dtu.msg_id = Json("m1");
    fired[0].dtu.guid = "dev";
    const Json wire = to_json(fired[0].dtu);
    CHECK(wire == Json::parse(R"({"@id":"m1","guid":"dev","id":")" + id +
                              R"(","time":19202912,"event":{"id":"tools","index":0,"oldValue":10,"value":5}})"));
}

TEST_CASE("value inbox: keeps only watched items and converts sample values") {
    ValueInbox inbox(3);
    inbox.push_value("a", 1, 1);  // nothing watched yet
    inbox.set_watched({"a", "b"});
    const std::vector<std::string> ids{"a", "z", "b"};
    const std::string warning = R"({"number":"7"})";
    const SampleValue values[] = {SampleValue::float64(1.5), SampleValue::int64(2), SampleValue::json(warning)};
    inbox.push_row(ids, values, 5);
    inbox.push_activation("event_1", std::nullopt, 6, {}, {});
    auto work = inbox.wait(std::chrono::milliseconds(0));
    REQUIRE(work.items.size() == 3);
    CHECK(work.items[0].id == "a");
    CHECK(*work.items[0].value == 1.5);
    CHECK(work.items[1].id == "b");
    CHECK(*work.items[1].value == Json{{"number", "7"}});
    CHECK(work.items[2].activation);
    CHECK(*sample_value_to_json(SampleValue::text("RUN")) == "RUN");
    CHECK(*sample_value_to_json(SampleValue::boolean(true)) == true);
    CHECK(*sample_value_to_json(SampleValue::uint64(7)) == 7);
    // Misses are no values: nothing to evaluate.
    CHECK_FALSE(sample_value_to_json(SampleValue::float64(std::numeric_limits<double>::quiet_NaN())));
    CHECK_FALSE(sample_value_to_json(SampleValue::null()));
    CHECK_FALSE(sample_value_to_json(SampleValue::json("{oops")));
}

TEST_CASE("value inbox: missed reads in sample rows are skipped") {
    ValueInbox inbox;
    inbox.set_watched({"a"});
    const std::vector<std::string> ids{"a"};
    const SampleValue miss[] = {SampleValue::null()};
    const SampleValue hit[] = {SampleValue::int64(3)};
    inbox.push_row(ids, miss, 1);
    inbox.push_row(ids, hit, 2);
    auto work = inbox.wait(std::chrono::milliseconds(0));
    REQUIRE(work.items.size() == 1);
    CHECK(*work.items[0].value == 3);
}

TEST_CASE("value inbox: bounded and closable") {
    ValueInbox inbox(2);
    inbox.set_watched({"a"});
    for (int i = 0; i < 5; ++i) inbox.push_value("a", i, i);
    inbox.push_activation("event_1", Json(1), 0, {}, {});  // never dropped
    CHECK(inbox.dropped() == 3);
    CHECK(inbox.wait(std::chrono::milliseconds(0)).items.size() == 3);
    CHECK(inbox.wait(std::chrono::milliseconds(1)).items.empty());
    inbox.close();
    CHECK(inbox.wait(std::nullopt).closed);
    inbox.push_value("a", 1, 1);
    CHECK(inbox.dropped() == 3);
}
