// The client library's events (src/client/client_events.cpp) against a real
// Adapter over the loopback broker.
#include "support/events_rig.hpp"
#include "support/collected.hpp"
#include "support/event_registration.hpp"

#include <nclink/client.hpp>

#include <future>

using namespace nclink;
using namespace nclink::test;

namespace {

struct ClientRig : EventsRig {
    ClientRig() {
        LoopbackOptions o;
        o.client_id = "client-app";
        ClientOptions options;
        options.ex_cid = "capp";
        options.default_timeout = std::chrono::seconds(5);
        client = Client::create(make_loopback_transport(broker, o), options).value();
        REQUIRE(client->start().ok());
        REQUIRE(client->wait_connected(std::chrono::seconds(5)));
    }
    ~ClientRig() { client->stop(); }

    nclink::test::Collected<EventData> seen;
    std::unique_ptr<Client> client;
};

}  // namespace

TEST_CASE("client events: the registration's first event reaches the callback after done") {
    ClientRig f;
    std::promise<std::string> done_id;
    std::atomic<std::size_t> events_when_done{99};
    f.client->register_event_async("test-dev", event_registration("ovr", {{{"type", "equal"}, {"value", 100}}}), f.seen.handler(),
                                   [&](Result<std::string> id) {
                                       events_when_done = f.seen.size();
                                       done_id.set_value(id.ok() ? *id : std::string());
                                   });
    const std::string id = done_id.get_future().get();
    REQUIRE_FALSE(id.empty());
    CHECK(events_when_done == 0);
    REQUIRE(eventually([&] { return f.seen.size() == 1; }));
    const EventData e = f.seen.at(0);
    CHECK(e.id == id);
    CHECK(e.guid == "test-dev");
    CHECK(e.event.id == "ovr");
    CHECK(e.event.value == 100);
    CHECK(f.client->stats().events == 1);
    CHECK(f.client->event_registrations() == 1);
}

TEST_CASE("client events: polled changes reach the callback with old and new value") {
    ClientRig f;
    auto id = f.client->register_event("test-dev", event_registration("ovr"), f.seen.handler());
    REQUIRE(id.ok());
    f.machine("ovr", 70);
    f.poll();
    REQUIRE(eventually([&] { return f.seen.size() == 1; }));
    CHECK(*f.seen.at(0).event.old_value == 100);
    CHECK(f.seen.at(0).event.value == 70);
}

TEST_CASE("client events: refusals come back as their table-19 codes") {
    ClientRig f;
    auto code = [&](Client::EventRegistration r) {
        auto id = f.client->register_event("test-dev", std::move(r), f.seen.handler());
        REQUIRE_FALSE(id.ok());
        return id.error().code;
    };
    CHECK(code(event_registration("nope")) == ErrorCode::node_not_exists);
    CHECK(code(event_registration("ovr", {{{"type", "bigger"}}})) == ErrorCode::filter_type);
    CHECK(code(event_registration("ovr", {}, "never")) == ErrorCode::trigger_type);
    CHECK(code(event_registration("ovr", {{{"type", "include"}, {"values", 1}}})) == ErrorCode::filter_arguments_mismatch);
    auto list = event_registration("tools");
    CHECK(code(list) == ErrorCode::no_index);
    list.index = 7;
    CHECK(code(list) == ErrorCode::out_of_range);
    CHECK(f.client->event_registrations() == 0);
}

TEST_CASE("client events: a once callback goes with its first event") {
    ClientRig f;
    REQUIRE(
        f.client
            ->register_event("test-dev", event_registration("ovr", {{{"type", "less"}, {"value", 50}}}, "once"), f.seen.handler())
            .ok());
    CHECK(f.client->event_registrations() == 1);
    f.machine("ovr", 10);
    f.poll();
    REQUIRE(eventually([&] { return f.seen.size() == 1; }));
    REQUIRE(eventually([&] { return f.client->event_registrations() == 0; }));
    CHECK(f.feature_stats()["registered"] == 0);
}

TEST_CASE("client events: unregister drops the callback and reports NG codes") {
    ClientRig f;
    auto id = f.client->register_event("test-dev", event_registration("ovr"), f.seen.handler());
    REQUIRE(id.ok());
    REQUIRE(f.client->unregister_event("test-dev", *id).ok());
    CHECK(f.client->event_registrations() == 0);
    auto again = f.client->unregister_event("test-dev", *id);
    REQUIRE_FALSE(again.ok());
    CHECK(again.error().code == ErrorCode::node_not_exists);
    // Another application's event.
    const auto theirs = f.registered({{"id", "ovr"}}, "app");
    auto stranger = f.client->unregister_event("test-dev", theirs);
    REQUIRE_FALSE(stranger.ok());
    CHECK(stranger.error().code == ErrorCode::permission_denied);
}

TEST_CASE("client events: unknown and malformed Event DTUs are counted and dropped") {
    ClientRig f;
    f.app->send("Event/test-dev/capp",
                R"({"@id":"x","guid":"test-dev","id":"event_unknown","time":1,"event":{"id":"a","value":1}})");
    f.app->send("Event/test-dev/capp", R"({"@id":"y","guid":"test-dev","id":"event_unknown"})");
    REQUIRE(eventually([&] { return f.client->stats().malformed == 1; }));
    REQUIRE(eventually([&] { return f.client->stats().unmatched_responses >= 1; }));
    CHECK(f.client->stats().events == 0);
}

TEST_CASE("client events: blocking calls from a callback answer unavailable") {
    ClientRig f;
    std::promise<ErrorCode> inner;
    auto id = f.client->register_event("test-dev", event_registration("ovr", {{{"type", "equal"}, {"value", 100}}}),
                                       [&](const EventData&) {
                                           auto r = f.client->register_event("test-dev", event_registration("ovr"), {});
                                           inner.set_value(r.ok() ? ErrorCode::success : r.error().code);
                                       });
    REQUIRE(id.ok());
    CHECK(inner.get_future().get() == ErrorCode::unavailable);
}
