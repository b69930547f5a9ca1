// The events feature of an Adapter, through the wire (loopback). This file is
// compiled again, through mosquitto, into the events integration tests
// (tests/integration/events/CMakeLists.txt): both response spellings,
// response-before-event order, every filter type and variance, every
// Register/Event error code, malformed requests, Event/{dev} without a
// terminal id. Triggers, elements, 416, release on offline and lease expiry
// have their mosquitto counterpart on the simulated machine
// (tests/integration/events/test_events_sim_mqtt.cpp).
#include "support/events_rig.hpp"

#include <set>

using namespace nclink;
using namespace nclink::test;

TEST_CASE("events adapter: register answers OK with an adapter-generated id") {
    EventsRig f;
    const Json reply = f.register_event(Json{{"@id", "some_mid_001"}, {"guid", "test-dev"}, {"id", "ovr"}});
    CHECK(reply["@id"] == "some_mid_001");
    CHECK(reply["guid"] == "test-dev");
    CHECK(reply["code"] == "OK");
    CHECK(reply["id"].get<std::string>().rfind("event_", 0) == 0);
    // Both spellings of the response topic (docs/wire.md, standard_typo_topics).
    CHECK(f.app->wait("Reigster/Event/Response/test-dev/app")["id"] == reply["id"]);
    CHECK(f.feature_stats()["registered"] == 1);
}

TEST_CASE("events adapter: a change filter fires when a polled value changes") {
    EventsRig f;
    const auto id = f.registered({{"id", "ovr"}});
    f.poll();  // still 100: nothing
    f.settle();
    CHECK(f.events().empty());
    f.machine("ovr", 50);
    f.poll();
    const Json e = f.event(1);
    CHECK(e["id"] == id);
    CHECK(e["guid"] == "test-dev");
    CHECK(e["@id"].is_string());
    CHECK(e["time"].is_number_integer());
    CHECK(e["time"].get<std::int64_t>() >= f.clock->wall_ms() - 1000);
    CHECK(e["event"] == Json{{"id", "ovr"}, {"oldValue", 100}, {"value", 50}});
    CHECK(f.feature_stats()["fired"] == 1);
}

TEST_CASE("events adapter: an event that already matches fires right after the response") {
    EventsRig f;
    const auto id = f.registered({{"id", "ovr"}, {"filters", {{{"type", "greater"}, {"value", 50}}}}});
    const Json e = f.event(1);
    CHECK(e["id"] == id);
    CHECK(e["event"] == Json{{"id", "ovr"}, {"value", 100}});  // no oldValue at registration
    // Published after the response: the application knows the id first.
    std::lock_guard<std::mutex> lock(f.app->mutex);
    std::size_t response_at = 0, event_at = 0;
    for (std::size_t i = 0; i < f.app->inbox.size(); ++i) {
        if (f.app->inbox[i].topic == "Register/Event/Response/test-dev/app") response_at = i;
        if (f.app->inbox[i].topic == "Event/test-dev/app") event_at = i;
    }
    CHECK(response_at < event_at);
}

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: normal fires on entering only and once releases the event") {
    EventsRig f;
    const auto normal = f.registered({{"id", "ovr"}, {"filters", {{{"type", "less"}, {"value", 50}}}}, {"triggerType", "normal"}});
    const auto once = f.registered({{"id", "ovr"}, {"filters", {{{"type", "less"}, {"value", 50}}}}, {"triggerType", "once"}});
    for (int v : {40, 30, 60, 20, 10}) {
        f.machine("ovr", v);
        f.poll();
    }
    f.settle();
    std::vector<std::pair<std::string, int>> seen;
    for (const auto& e : f.events()) seen.emplace_back(e["id"].get<std::string>(), e["event"]["value"].get<int>());
    CHECK(seen == std::vector<std::pair<std::string, int>>{{normal, 40}, {once, 40}, {normal, 20}});
    CHECK(f.feature_stats()["registered"] == 1);
    CHECK(f.feature_stats()["released"] == 1);
    CHECK(f.unregister_event(once)["error"] == 401);  // released by the adapter already
}
#endif

TEST_CASE("events adapter: every filter type through the wire") {
    EventsRig f;
    f.machine("status", "free");  // STATUS words of table 15: the SDK refuses others (chapter 7)
    const auto equal = f.registered({{"id", "status"}, {"filters", {{{"type", "equal"}, {"value", "holding"}}}}});
    const auto include = f.registered({{"id", "status"}, {"filters", {{{"type", "include"}, {"values", {"running"}}}}}});
    const auto range = f.registered({{"id", "ovr"}, {"filters", {{{"type", "range"}, {"from", 100}, {"to", 120}}}}});
    const auto greater = f.registered({{"id", "ovr"}, {"filters", {{{"type", "greater"}, {"value", 119}}}}});
    const auto change = f.registered({{"id", "ovr"}, {"filters", {{{"type", "change"}, {"variance", 10}}}}});
    f.machine("status", "running");
    f.machine("ovr", 110);
    f.poll();
    f.machine("status", "holding");
    f.machine("ovr", 120);
    f.poll();
    f.machine("ovr", 125);  // only 5 away from the last change event (120): no change event, greater fires
    f.poll();
    f.settle();
    std::multiset<std::pair<std::string, Json>> seen;
    for (const auto& e : f.events()) seen.emplace(e["id"].get<std::string>(), e["event"]["value"]);
    const std::multiset<std::pair<std::string, Json>> expected{
        {include, "running"}, {range, 110}, {change, 110}, {equal, "holding"}, {greater, 120}, {change, 120}, {greater, 125}};
    CHECK(seen == expected);
}

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: dict and list elements") {
    EventsRig f;
    const auto dict = f.registered({{"id", "params"}, {"key", "p1"}});
    const auto list = f.registered({{"id", "tools"}, {"index", 1}, {"filters", {{{"type", "change"}}}}});
    // Change through a Set request (the driver keeps the new value).
    const Json set = f.set(Json::array({Json{{"id", "params"}, {"params", {{"key", "p2"}, {"value", 9}}}}}));
    REQUIRE(set["results"][0]["code"] == "OK");
    f.poll();
    f.settle();
    CHECK(f.events().empty());  // p2 changed, not p1
    REQUIRE(f.set(Json::array({Json{{"id", "params"}, {"params", {{"key", "p1"}, {"value", 7}}}}}))["results"][0]["code"] ==
            "OK");
    f.machine("tools", Json::array({Json{{"id", "T1"}}, Json{{"id", "T9"}}, Json{{"id", "T3"}}}));
    f.poll();
    f.settle();
    std::map<std::string, Json> by_id;
    for (const auto& e : f.events()) by_id[e["id"].get<std::string>()] = e["event"];
    CHECK(by_id[dict] == Json{{"id", "params"}, {"key", "p1"}, {"oldValue", 1}, {"value", 7}});
    CHECK(by_id[list] ==
          Json{{"id", "tools"}, {"index", 1}, {"oldValue", {{"id", "T2"}, {"length", 75.5}}}, {"value", {{"id", "T9"}}}});
}
#endif

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: SDK-held configuration values are watched too") {
    EventsRig f;
    const auto id = f.registered({{"id", "feed_ovr_cfg"}, {"filters", {{{"type", "greater"}, {"value", 100}}}}});
    REQUIRE(f.set(Json::array({Json{{"id", "feed_ovr_cfg"}, {"params", {{"value", 110}}}}}))["results"][0]["code"] == "OK");
    f.poll();
    const Json e = f.event(1);
    CHECK(e["id"] == id);
    CHECK(e["event"]["value"] == 110);
    CHECK(e["event"]["oldValue"] == 100);
}
#endif

TEST_CASE("events adapter: error codes of Register/Event") {
    AdapterConfig c = events_config(8);
    EventsRig f(c);
    auto code = [&](Json body) {
        const Json reply = f.register_event(std::move(body));
        INFO(reply.dump());
        CHECK(reply["code"] == "NG");
        CHECK(reply["guid"] == "test-dev");
        CHECK(reply["id"] == "");  // table 49: present in every answer, empty when refused
        return reply["error"].get<int>();
    };
    CHECK(code({{"id", "nope"}}) == 401);
    CHECK(code({{"id", "tools"}}) == 402);
    CHECK(code({{"id", "params"}}) == 403);
    CHECK(code({{"id", "ovr"}, {"filters", {{{"type", "between"}}}}}) == 419);
    CHECK(code({{"id", "ovr"}, {"triggerType", "sometimes"}}) == 420);
    CHECK(code({{"id", "ovr"}, {"filters", {{{"type", "change"}, {"from", 1}}}}}) == 421);
    CHECK(code({{"id", "params"}, {"key", "missing"}}) == 410);
    CHECK(code({{"id", "tools"}, {"index", 3}}) == 101);
    CHECK(code({{"id", "ovr"}, {"key", "k"}}) == 409);
    // Reasons are the exact table-19 strings.
    CHECK(f.register_event({{"id", "ovr"}, {"triggerType", "x"}})["reason"] == "trigger type error");
    CHECK(f.feature_stats()["registered"] == 0);
}

TEST_CASE("events adapter: malformed requests still get an answer") {
    EventsRig f;
    const auto reply_topic = topics::event_register_response("test-dev", "app");
    const Json not_json = f.app->request(topics::event_register_request("test-dev", "app"), reply_topic, Json("x{"));
    CHECK(not_json["code"] == "NG");
    f.app->send(topics::event_register_request("test-dev", "app"), "{not json");
    CHECK(f.app->wait(reply_topic, 2)["error"] == 412);
    const Json no_trigger =
        f.app->request(topics::event_register_request("test-dev", "app"), reply_topic, Json{{"@id", "m1"}, {"id", "ovr"}});
    CHECK(no_trigger["@id"] == "m1");
    CHECK(no_trigger["error"] == 102);
    const Json bad_unregister = f.app->request(topics::event_unregister_request("test-dev", "app"),
                                               topics::event_unregister_response("test-dev", "app"), Json{{"@id", "m2"}});
    CHECK(bad_unregister["code"] == "NG");
    CHECK(bad_unregister["@id"] == "m2");
}

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: resources full answers 416 until one is released") {
    EventsRig f(events_config(2));
    const auto first = f.registered({{"id", "ovr"}});
    (void)f.registered({{"id", "status"}}, "other");
    const Json full = f.register_event({{"id", "ovr"}});
    CHECK(full["error"] == 416);
    CHECK(full["reason"] == "Insufficient event resources");
    REQUIRE(f.unregister_event(first)["code"] == "OK");
    (void)f.registered({{"id", "ovr"}});
}
#endif

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: unregister stops the events and refuses strangers") {
    EventsRig f;
    const auto id = f.registered({{"id", "ovr"}});
    const Json stranger = f.unregister_event(id, "other");
    CHECK(stranger["code"] == "NG");
    CHECK(stranger["error"] == 301);
    CHECK(stranger["reason"] == "Permission Denied");
    CHECK(f.unregister_event("event_nope")["error"] == 401);
    const Json ok = f.unregister_event(id);
    CHECK(ok["code"] == "OK");
    CHECK(ok["guid"] == "test-dev");
    CHECK_FALSE(ok.contains("id"));  // table 51 has no id
    f.machine("ovr", 1);
    f.settle();
    f.clock->advance(std::chrono::milliseconds(500));
    f.settle();
    CHECK(f.events().empty());
    CHECK(f.feature_stats()["released"] == 1);
}
#endif

TEST_CASE("events adapter: a registration without terminal id publishes on Event/dev") {
    EventsRig f;
    const Json reply = f.app->request(
        topics::event_register_request("test-dev"), topics::event_register_response("test-dev"),
        Json{{"@id", "x1"}, {"id", "ovr"}, {"filters", {{{"type", "equal"}, {"value", 100}}}}, {"triggerType", "always"}});
    REQUIRE(reply["code"] == "OK");
    CHECK(f.app->wait("Event/test-dev")["id"] == reply["id"]);
}

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: events of an application that went offline are released") {
    EventsRig f;
    (void)f.registered({{"id", "ovr"}}, "gone");
    (void)f.registered({{"id", "ovr"}}, "stays");
    f.app->send("Notify/State/gone", R"({"tid":"gone","state":"offline"})");
    REQUIRE(eventually([&] { return f.feature_stats()["registered"] == 1; }));
    f.machine("ovr", 1);
    f.poll();
    CHECK(f.event(1, "stays")["event"]["value"] == 1);
    f.settle();
    CHECK(f.events("gone").empty());
}
#endif

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: events of an application silent for the lease are released") {
    AdapterConfig c = events_config();
    c.application_lease = std::chrono::milliseconds(1000);
    EventsRig f(c);
    (void)f.registered({{"id", "ovr"}}, "quiet");
    f.clock->advance(std::chrono::milliseconds(600));
    (void)f.registered({{"id", "ovr"}}, "chatty");
    f.clock->advance(std::chrono::milliseconds(600));  // quiet: 1200 ms silent; chatty: 600
    REQUIRE(eventually([&] { return f.feature_stats()["registered"] == 1; }));
    CHECK(f.feature_stats()["released"] == 1);
}
#endif

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: notify_value makes an event without polling") {
    EventsRig f(events_config(8, std::chrono::milliseconds(0)));  // polling off
    const auto id = f.registered({{"id", "status"}});
    f.adapter->notify_value("status", "free");
    const Json e = f.event(1);
    CHECK(e["id"] == id);
    CHECK(e["event"] == Json{{"id", "status"}, {"oldValue", "running"}, {"value", "free"}});
    f.adapter->notify_value("ovr", 5);          // nobody watches it: ignored
    f.adapter->notify_value("status", "free");  // same value: no change
    f.settle();
    CHECK(f.events().size() == 1);
    CHECK(f.feature_stats()["polls"] == 0);
}
#endif

#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO  // on the sim through mosquitto: tests/integration/events
TEST_CASE("events adapter: a new model releases events of items it lost") {
    EventsRig f;
    (void)f.registered({{"id", "status"}});
    (void)f.registered({{"id", "ovr"}});
    Json model = model_to_json(*f.adapter->model());
    auto& items = model["devices"][0]["dataItems"];
    for (auto it = items.begin(); it != items.end(); ++it)
        if ((*it)["id"] == "status") {
            items.erase(it);
            break;
        }
    model["devices"][0]["version"] = "1.0.1";
    const Json reply = f.app->request(topics::probe_set_request("test-dev", "app"), topics::probe_set_response("test-dev", "app"),
                                      Json{{"@id", "p1"}, {"guid", "test-dev"}, {"probe", model}});
    REQUIRE(reply["code"] == "OK");
    CHECK(f.feature_stats()["registered"] == 1);
    CHECK(f.feature_stats()["released"] == 1);
}
#endif
