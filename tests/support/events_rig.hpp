// An adapter (FakeDriver, test model) with the events feature, talked to
// through the wire by an application side: Register/Event, Unregister/Event
// and the Event DTUs it receives. Loopback by default, a real mosquitto
// when NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO is defined (adapter_fixture.hpp).
#pragma once

#include "support/adapter_fixture.hpp"

#include <nclink/topics.hpp>

namespace nclink::test {

inline AdapterConfig events_config(std::size_t max_events = 8, std::chrono::milliseconds poll = std::chrono::milliseconds(100)) {
    AdapterConfig c;
    // These tests watch by polling and pushes; the sample stream has its own
    // tests (test_events_service.cpp, and on the sim in tests/integration/events).
    c.sampling.enabled = false;
    c.events.max_events = max_events;
    c.events.poll_interval = poll;
    return c;
}

struct EventsRig : AdapterFixture {
    explicit EventsRig(AdapterConfig c = events_config()) : AdapterFixture(std::move(c)) {}

    Json register_event(Json body, const std::string& ex = "app") {
        if (!body.contains("@id")) body["@id"] = "r" + std::to_string(++counter);
        if (!body.contains("triggerType")) body["triggerType"] = "always";
        return app->request(topics::event_register_request("test-dev", ex), topics::event_register_response("test-dev", ex), body);
    }
    /// Registers and requires OK; returns the event id.
    std::string registered(Json body, const std::string& ex = "app") {
        const Json reply = register_event(std::move(body), ex);
        INFO(reply.dump());
        REQUIRE(reply["code"] == "OK");
        REQUIRE(reply["id"].is_string());
        return reply["id"].get<std::string>();
    }
    Json unregister_event(const std::string& id, const std::string& ex = "app") {
        return app->request(topics::event_unregister_request("test-dev", ex), topics::event_unregister_response("test-dev", ex),
                            Json{{"@id", "u" + std::to_string(++counter)}, {"guid", "test-dev"}, {"id", id}});
    }
    std::vector<Json> events(const std::string& ex = "app") {
        std::vector<Json> out;
        for (const auto& m : app->on(topics::event("test-dev", ex))) out.push_back(Json::parse(m.payload));
        return out;
    }
    /// Waits for the n-th event to `ex`.
    Json event(std::size_t n, const std::string& ex = "app") { return app->wait(topics::event("test-dev", ex), n); }

    void machine(const std::string& id, Json value) {
        std::lock_guard<std::mutex> lock(driver->mutex);
        driver->values[id] = std::move(value);
    }
    Json feature_stats() { return adapter->stats().features["events"]; }
    /// One poll period on the manual clock; returns once that poll round has
    /// published what it fired.
    void poll() {
        const auto before = feature_stats()["polls"].get<std::uint64_t>();
        clock->advance(config.events.poll_interval);
        REQUIRE(eventually([&] { return feature_stats()["polls"].get<std::uint64_t>() > before; }));
    }
    /// Everything sent so far has been routed to the application (a request
    /// round trip behind it).
    void settle() { (void)query(Json::array({"ovr"})); }
};

}  // namespace nclink::test
