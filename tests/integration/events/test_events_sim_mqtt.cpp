// Events end to end: the simulated mill behind an Adapter, a real mosquitto,
// and applications using the client library and the `nclink events` CLI.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include "sim/sim_driver.hpp"
#include <nclink/topics.hpp>

#include "support/cli.hpp"
#include "support/collected.hpp"
#include "support/event_registration.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <future>
#include <mutex>
#include <thread>

using namespace nclink;
using nclink::test::cli_built;
using nclink::test::run_cli;
using Run = nclink::test::CliRun;
using nclink::test::event_registration;
using nclink::test::eventually;

namespace {

const std::string kDev = nclink::test::kSimMillDevice;

/// Event DTUs a callback received, for the test thread.
using Seen = nclink::test::Collected<EventData>;

struct Rig : nclink::test::SimMillRig {
    explicit Rig(std::size_t max_events = 8, std::chrono::milliseconds lease = std::chrono::minutes(5)) {
        config.events.max_events = max_events;
        config.events.poll_interval = std::chrono::milliseconds(50);
        config.application_lease = lease;
        start();
        client = make_client("app");
    }
    Json stats() { return adapter->stats().features["events"]; }
};

ErrorCode refused(Rig& rig, Client::EventRegistration r) {
    Seen seen;
    auto id = rig.client->register_event(kDev, std::move(r), seen.handler());
    REQUIRE_FALSE(id.ok());
    return id.error().code;
}

}  // namespace

TEST_CASE("events on the sim: a greater filter fires when a Set moves the value") {
    Rig rig;
    rig.set_one("feed_override", {{"value", 100}});
    Seen seen;
    auto id = rig.client->register_event(kDev, event_registration("feed_override", {{{"type", "greater"}, {"value", 110}}}),
                                         seen.handler());
    REQUIRE(id.ok());
    rig.set_one("feed_override", {{"value", 120}});
    REQUIRE(eventually([&] { return seen.size() == 1; }));
    const EventData e = seen.at(0);
    CHECK(e.id == *id);
    CHECK(e.guid == kDev);
    CHECK(e.event.id == "feed_override");
    CHECK(e.event.value == 120);
    REQUIRE(e.event.old_value);
    CHECK(*e.event.old_value == 100);
    CHECK(rig.client->stats().events == 1);
    REQUIRE(rig.client->unregister_event(kDev, *id).ok());
    CHECK(rig.stats()["registered"] == 0);
}

TEST_CASE("events on the sim: each trigger type") {
    Rig rig;
    rig.set_one("spindle_override", {{"value", 100}});
    const Json below{{"type", "less"}, {"value", 90}};
    Seen always, normal, once;
    REQUIRE(rig.client->register_event(kDev, event_registration("spindle_override", {below}, "always"), always.handler()).ok());
    REQUIRE(rig.client->register_event(kDev, event_registration("spindle_override", {below}, "normal"), normal.handler()).ok());
    REQUIRE(rig.client->register_event(kDev, event_registration("spindle_override", {below}, "once"), once.handler()).ok());
    CHECK(rig.client->event_registrations() == 3);
    for (int v : {80, 70, 95, 60}) {
        rig.set_one("spindle_override", {{"value", v}});
        // Each value stays long enough for a poll (50 ms) to see it.
        REQUIRE(eventually([&] { return rig.query_one("spindle_override") == v; }));
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    REQUIRE(eventually([&] { return always.size() == 3; }));
    CHECK(always.at(0).event.value == 80);
    CHECK(always.at(1).event.value == 70);
    CHECK(always.at(2).event.value == 60);
    REQUIRE(eventually([&] { return normal.size() == 2; }));
    CHECK(normal.at(0).event.value == 80);
    CHECK(normal.at(1).event.value == 60);
    CHECK(once.size() == 1);
    CHECK(once.at(0).event.value == 80);
    CHECK(rig.client->event_registrations() == 2);  // the once callback went with its event
    CHECK(rig.stats()["registered"] == 2);
}

TEST_CASE("events on the sim: a sampled item is watched from the sample stream") {
    Rig rig;
    // x_position is in the model's ch_fast channel and moves while the
    // simulated program runs.
    Seen seen;
    auto id = rig.client->register_event(kDev, event_registration("x_position", {{{"type", "change"}, {"variance", 0.5}}}),
                                         seen.handler());
    REQUIRE(id.ok());
    REQUIRE(eventually([&] { return seen.size() >= 3; }));
    REQUIRE(rig.client->unregister_event(kDev, *id).ok());
    CHECK(rig.stats()["polls"] == 0);  // nothing was polled: the rows brought every value
    for (std::size_t i = 1; i < 3; ++i) {
        const EventData e = seen.at(i);
        INFO(encode(e));
        REQUIRE(e.event.old_value);
        CHECK(e.event.value.is_number());
        CHECK(std::abs(e.event.value.get<double>() - seen.at(i - 1).event.value.get<double>()) >= 0.5);
    }
}

TEST_CASE("events on the sim: an event that matches at registration fires at once") {
    Rig rig;
    rig.set_one("feed_override", {{"value", 100}});
    Seen seen;
    auto id = rig.client->register_event(kDev, event_registration("feed_override", {{{"type", "equal"}, {"value", 100}}}),
                                         seen.handler());
    REQUIRE(id.ok());
    REQUIRE(eventually([&] { return seen.size() == 1; }));
    CHECK(seen.at(0).event.value == 100);
    CHECK_FALSE(seen.at(0).event.old_value);
}

TEST_CASE("events on the sim: dict and list elements") {
    Rig rig;
    const Json p1 = rig.query_one("parameters", {{"keys", {"P0001"}}});
    Seen dict, list;
    auto reg_dict = event_registration("parameters", {{{"type", "change"}, {"variance", 10}}});
    reg_dict.key = "P0001";
    REQUIRE(rig.client->register_event(kDev, reg_dict, dict.handler()).ok());
    auto reg_list = event_registration("tools");
    reg_list.index = 0;
    REQUIRE(rig.client->register_event(kDev, reg_list, list.handler()).ok());

    rig.set_one("parameters", {{"key", "P0001"}, {"value", p1.get<double>() + 1}});  // below the variance? first event: no check
    REQUIRE(eventually([&] { return dict.size() == 1; }));
    CHECK(dict.at(0).event.key == std::optional<std::string>("P0001"));
    CHECK(dict.at(0).event.value == p1.get<double>() + 1);
    rig.set_one("parameters", {{"key", "P0001"}, {"value", p1.get<double>() + 5}});  // 4 from the last event
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    rig.set_one("parameters", {{"key", "P0001"}, {"value", p1.get<double>() + 20}});  // 19: fires
    REQUIRE(eventually([&] { return dict.size() == 2; }));
    CHECK(dict.at(1).event.value == p1.get<double>() + 20);
    CHECK(*dict.at(1).event.old_value == p1.get<double>() + 5);

    Json tool = rig.query_one("tools", {{"indexes", {"0"}}});
    const Json before = tool;
    tool["length"] = 123.25;
    rig.set_one("tools", {{"index", 0}, {"value", tool}});
    REQUIRE(eventually([&] { return list.size() == 1; }));
    CHECK(list.at(0).event.index == std::optional<std::int64_t>(0));
    CHECK(list.at(0).event.value == tool);
    CHECK(*list.at(0).event.old_value == before);
}

TEST_CASE("events on the sim: every refusal reaches the client as its table-19 code") {
    Rig rig(2);
    CHECK(refused(rig, event_registration("no_such_item")) == ErrorCode::node_not_exists);
    CHECK(refused(rig, event_registration("tools")) == ErrorCode::no_index);
    CHECK(refused(rig, event_registration("parameters")) == ErrorCode::no_key);
    CHECK(refused(rig, event_registration("feed_override", {{{"type", "between"}}})) == ErrorCode::filter_type);
    CHECK(refused(rig, event_registration("feed_override", {}, "sometimes")) == ErrorCode::trigger_type);
    CHECK(refused(rig, event_registration("feed_override", {{{"type", "change"}, {"from", 1}}})) ==
          ErrorCode::filter_arguments_mismatch);
    auto missing_key = event_registration("parameters");
    missing_key.key = "NOPE";
    CHECK(refused(rig, missing_key) == ErrorCode::key_error);
    // Resource exhaustion, then a release frees a slot.
    Seen seen;
    auto a = rig.client->register_event(kDev, event_registration("feed_override"), seen.handler());
    REQUIRE(a.ok());
    REQUIRE(rig.client->register_event(kDev, event_registration("spindle_override"), seen.handler()).ok());
    CHECK(refused(rig, event_registration("status")) == ErrorCode::insufficient_event);
    // Unregister: unknown, another application's, then the owner's.
    auto other = rig.make_client("other");
    auto stranger = other->unregister_event(kDev, *a);
    REQUIRE_FALSE(stranger.ok());
    CHECK(stranger.error().code == ErrorCode::permission_denied);
    CHECK(rig.client->unregister_event(kDev, "event_nope").error().code == ErrorCode::node_not_exists);
    REQUIRE(rig.client->unregister_event(kDev, *a).ok());
    CHECK(rig.client->register_event(kDev, event_registration("status"), seen.handler()).ok());
    other->stop();
}

TEST_CASE("events on the sim: events of an application that goes offline are released") {
    Rig rig;
    auto leaving = rig.make_client("leaving");
    Seen seen;
    REQUIRE(leaving->register_event(kDev, event_registration("feed_override"), seen.handler()).ok());
    REQUIRE(rig.client->register_event(kDev, event_registration("feed_override"), seen.handler()).ok());
    CHECK(rig.stats()["registered"] == 2);
    // What an agent (or the application's last will) publishes when it leaves.
    MqttOptions m;
    m.broker_url = rig.broker.url();
    m.client_id = "nclink-itest-notifier";
    auto notifier = make_mqtt_transport(m).value();
    REQUIRE(notifier->start().ok());
    REQUIRE(eventually([&] { return notifier->state() == LinkState::connected; }));
    REQUIRE(notifier->publish(Message{topics::notify_state("leaving"), R"({"tid":"leaving","state":"offline"})", 1, false}).ok());
    REQUIRE(eventually([&] { return rig.stats()["registered"] == 1; }));
    CHECK(rig.stats()["released"] == 1);
    notifier->stop();
    leaving->stop();
}

TEST_CASE("events on the sim: events of an application silent for the lease are released") {
    Rig rig(8, std::chrono::milliseconds(600));
    Seen seen;
    REQUIRE(rig.client->register_event(kDev, event_registration("feed_override"), seen.handler()).ok());
    CHECK(rig.stats()["registered"] == 1);
    REQUIRE(eventually([&] { return rig.stats()["registered"] == 0; }));
    CHECK(rig.stats()["released"] == 1);
}

TEST_CASE("events on the sim: nclink events prints the events live") {
    if (!cli_built()) {
        WARN("bin/nclink not built: skipped");
        return;
    }
    Rig rig;
    rig.set_one("feed_override", {{"value", 100}});
    auto cli = std::async(std::launch::async, [&] {
        return run_cli("events --broker " + rig.broker.url() + " --device " + kDev +
                       " feed_override --filter greater:110 --filter equal:50 --count 2 --json --timeout 5000");
    });
    REQUIRE(eventually([&] { return rig.stats()["registered"] == 1; }));
    rig.set_one("feed_override", {{"value", 120}});
    REQUIRE(eventually([&] { return rig.stats()["fired"] == 1; }));
    rig.set_one("feed_override", {{"value", 50}});
    const Run run = cli.get();
    CHECK(run.status == 0);
    std::vector<Json> lines;
    std::size_t start = 0;
    while (start < run.out.size()) {
        const auto end = run.out.find('\n', start);
        lines.push_back(Json::parse(run.out.substr(start, end - start)));
        start = end == std::string::npos ? run.out.size() : end + 1;
    }
    REQUIRE(lines.size() == 2);
    CHECK(lines[0]["event"]["value"] == 120);
    CHECK(lines[1]["event"]["value"] == 50);
    CHECK(lines[1]["event"]["oldValue"] == 120);
    // It unregistered on the way out.
    REQUIRE(eventually([&] { return rig.stats()["registered"] == 0; }));
}

TEST_CASE("events on the sim: nclink events exit codes") {
    if (!cli_built()) {
        WARN("bin/nclink not built: skipped");
        return;
    }
    Rig rig;
    CHECK(run_cli("events --broker " + rig.broker.url() + " --device " + kDev + " no_such_item").status == 1);
    CHECK(run_cli("events --broker " + rig.broker.url() + " " + kDev + " feed_override --filter bogus:1").status == 2);
    CHECK(run_cli("events --broker " + rig.broker.url() + " --device " + kDev + " feed_override --trigger maybe").status == 2);
    CHECK(run_cli("events --broker " + rig.broker.url() + " --device " + kDev).status == 2);
    // A refused filter is the adapter's answer (421): exit 1.
    CHECK(run_cli("events --broker " + rig.broker.url() + " " + kDev + " feed_override --filter '{\"type\":\"change\",\"from\":1}'")
              .status == 1);
    // once: the first event ends it.
    rig.set_one("feed_override", {{"value", 100}});
    const Run once =
        run_cli("events --broker " + rig.broker.url() + " " + kDev + " feed_override --filter equal:100 --trigger once");
    CHECK(once.status == 0);
    CHECK(once.out.find("feed_override 100") != std::string::npos);
}
