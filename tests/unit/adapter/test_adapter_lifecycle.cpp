// Adapter lifecycle: model refusal, Probe/Query and Probe/Set, persistence,
// registration, the state machine on link changes, clean stop.
#include "support/adapter_fixture.hpp"
#include "support/heap_cycle.hpp"

#include <nclink/model.hpp>

#include <fstream>

using namespace nclink;
using namespace nclink::test;

TEST_CASE("a model with fatal problems is refused with every problem listed") {
    AdapterConfig c;
    c.model_path = std::string(NCLINK_MODELS_DIR) + "/invalid/duplicate-id.json";
    LoopbackBroker broker;
    Adapter adapter(c, std::make_shared<FakeDriver>());
    adapter.use_transport(make_loopback_transport(broker, {"adapter", std::nullopt, {}}));
    auto r = adapter.start();
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::syntax_error);
    CHECK_THAT(r.error().message, Catch::Contains("fatal"));
    CHECK_THAT(r.error().message, Catch::Contains("duplicate"));
}

TEST_CASE("strict mode refuses conformance problems, the default runs the file") {
    AdapterConfig c;
    c.model_path = std::string(NCLINK_MODELS_DIR) + "/appendix-b.json";
    c.strict = true;
    {
        LoopbackBroker broker;
        Adapter adapter(c, std::make_shared<FakeDriver>());
        adapter.use_transport(make_loopback_transport(broker, {"adapter", std::nullopt, {}}));
        auto r = adapter.start();
        REQUIRE_FALSE(r.ok());
        CHECK_THAT(r.error().message, Catch::Contains("(strict)"));
        CHECK_THAT(r.error().message, Catch::Contains("settable"));
    }
    c.strict = false;
    LoopbackBroker broker;
    Adapter adapter(c, std::make_shared<FakeDriver>());
    adapter.use_transport(make_loopback_transport(broker, {"adapter", std::nullopt, {}}));
    REQUIRE(adapter.start().ok());
    CHECK(adapter.dev_uuid() == "0103");  // appendix B has no guid: the device id
    CHECK_FALSE(adapter.model_problems().empty());
    adapter.stop();
}

TEST_CASE("the dev_uuid override from the configuration wins") {
    AdapterConfig c;
    c.dev_uuid = "line3-mill7";
    AdapterFixture f(c, false);
    f.start();
    CHECK(f.adapter->dev_uuid() == "line3-mill7");
}

// The heap policy is process-wide: the second case sets the program's own
// policy first, so it also holds when the cases share a process.
TEST_CASE("start keeps freed heap for the uploader's next DTUs by default") {
    AdapterFixture f;
    if (sanitized_allocator()) return;  // mallopt does nothing under a sanitizer
    CHECK(faults_after_first_burst(5, kKeptBurstBlocks) < 40);
}

TEST_CASE("heap_keep_bytes 0 leaves the allocator as the program set it") {
    AdapterConfig c;
    c.heap_keep_bytes = 0;
    set_initial_heap_policy();
    AdapterFixture f(c);
    if (sanitized_allocator()) return;
    CHECK(faults_after_first_burst() > 400);  // glibc's initial policy: trimmed after every burst
}

TEST_CASE("Probe/Query returns the model as a JSON object, an empty payload works") {
    AdapterFixture f;
    const Json r = f.app->request("Probe/Query/Request/test-dev/app", "Probe/Query/Response/test-dev/app",
                                  Json{{"@id", "p1"}, {"guid", "test-dev"}});
    CHECK(r["code"] == "OK");
    REQUIRE(r["probe"].is_object());
    CHECK(r["probe"]["devices"][0]["guid"] == "test-dev");
    f.app->send("Probe/Query/Request/test-dev", "");
    CHECK(f.app->wait("Probe/Query/Response/test-dev")["probe"].is_object());
}

TEST_CASE("Probe/Set validates, persists, swaps the model and announces the new version") {
    AdapterFixture f;
    const std::string dir = f.config.persistence_dir;
    std::shared_ptr<const Model> seen;
    std::mutex mutex;
    f.adapter->add_model_listener([&](std::shared_ptr<const Model> m) {
        std::lock_guard<std::mutex> lock(mutex);
        seen = std::move(m);
    });
    Json model = Json::parse(std::ifstream(test_model_path()));
    model["devices"][0]["version"] = "1.1.0";
    model["devices"][0]["dataItems"].push_back(Json{{"id", "temp"}, {"type", "TEMPERATURE"}});

    SECTION("a valid model (given as a string) is taken") {
        const Json r = f.app->request("Probe/Set/Request/test-dev/app", "Probe/Set/Response/test-dev/app",
                                      Json{{"@id", "ps"}, {"guid", "test-dev"}, {"probe", model.dump()}});
        CHECK(r["code"] == "OK");
        CHECK(f.app->wait("Probe/Version/test-dev", 2)["version"] == "1.1.0");
        CHECK(f.adapter->model()->data_object("temp") != nullptr);
        {
            std::lock_guard<std::mutex> lock(mutex);
            REQUIRE(seen != nullptr);
            CHECK(seen->data_object("temp") != nullptr);
        }
        REQUIRE(std::filesystem::exists(std::filesystem::path(dir) / "model.json"));
        // A restarted adapter comes back with the model of the last Probe/Set.
        f.adapter->stop();
        f.adapter.reset();
        f.start();
        CHECK(f.adapter->model()->device("dev-1")->version == "1.1.0");
    }
    SECTION("an unusable model is refused with every problem listed; nothing changes") {
        model["devices"][0]["dataItems"].push_back(Json{{"id", "pos"}, {"type", "POSITION"}});
        model["devices"][0]["configs"][2]["sampleInterval"] = -5;
        const Json r = f.app->request("Probe/Set/Request/test-dev/app", "Probe/Set/Response/test-dev/app",
                                      Json{{"@id", "bad"}, {"probe", model}});
        CHECK(r["code"] == "NG");
        CHECK(r["error"] == 412);
        CHECK(r["reason"] == "syntax error");  // table 20: the table-19 string; the problems in privateInfo
        const std::string problems = r["privateInfo"]["problems"];
        CHECK_THAT(problems, Catch::Contains("duplicate"));
        CHECK_THAT(problems, Catch::Contains("sampleInterval"));
        CHECK(f.adapter->model()->data_object("temp") == nullptr);
        CHECK_FALSE(std::filesystem::exists(std::filesystem::path(dir) / "model.json"));
    }
    SECTION("a probe that is not JSON at all") {
        const Json r = f.app->request("Probe/Set/Request/test-dev/app", "Probe/Set/Response/test-dev/app",
                                      Json{{"@id", "junk"}, {"probe", "{{{"}});
        CHECK(r["code"] == "NG");
    }
}

TEST_CASE("settable SDK-held values survive a restart") {
    AdapterFixture f;
    CHECK(f.set(Json::array({Json{{"id", "feed_ovr_cfg"}, {"params", {{"value", 42}}}}}))["results"][0]["code"] == "OK");
    f.adapter->stop();
    f.adapter.reset();
    f.start();
    CHECK(f.query(Json::array({Json{{"id", "feed_ovr_cfg"}}}))["values"][0]["values"] == Json::array({42}));
}

TEST_CASE("registration: an agent's OK is recorded, without an agent the adapter serves and retries") {
    AdapterFixture f;
    const Json first = f.app->wait("Register/Request", 1);
    CHECK_FALSE(f.adapter->stats().registered);
    // No agent: after the timeout and a back-off (on the adapter's clock) it
    // registers again. Time moves only when the test moves it.
    REQUIRE(eventually([&] {
        f.clock->advance(std::chrono::milliseconds(50));
        return f.app->on("Register/Request").size() >= 2;
    }));
    const Json second = f.app->wait("Register/Request", 2);
    CHECK(second["@id"] == first["@id"]);  // the same request again: an agent never takes it for a second registration
    CHECK(f.query(Json::array({Json{{"id", "pos"}}}))["values"][0]["code"] == "OK");  // served all along
    // An agent answers the pending request.
    RegisterResponse ok;
    ok.msg_id = second["@id"];
    ok.cli_uuid = "test-dev";
    f.app->send("Register/Response/test-dev", encode(ok));
    REQUIRE(eventually([&] { return f.adapter->stats().registered; }));
}

TEST_CASE("the state machine follows the link, requests during an outage are answered after it") {
    AdapterFixture f;
    CHECK(f.adapter->state() == AdapterState::normal);
    f.broker.set_online(false);
    REQUIRE(eventually([&] { return f.adapter->state() == AdapterState::disconnected; }));
    // The broker published the adapter's will while it was away.
    CHECK(f.broker.retained("Notify/State/test-dev")->payload.find("offline") != std::string::npos);
    f.broker.set_online(true);
    REQUIRE(eventually([&] { return f.adapter->state() == AdapterState::normal; }));
    // After reconnecting it announces itself again (online state; and 8.3.6:
    // registers again, which the app may miss if it resubscribes later).
    REQUIRE(eventually([&] {
        auto retained = f.broker.retained("Notify/State/test-dev");
        return retained && retained->payload.find("online") != std::string::npos;
    }));
    CHECK(f.query(Json::array({Json{{"id", "pos"}}}))["values"][0]["code"] == "OK");
}

TEST_CASE("an abrupt drop publishes the offline will, a clean stop publishes offline itself") {
    AdapterFixture f;
    f.app->wait("Notify/State/test-dev", 1);
    REQUIRE(f.broker.drop_client("adapter"));
    CHECK(f.app->wait("Notify/State/test-dev", 2)["state"] == "offline");
    CHECK(f.app->wait("Notify/State/test-dev", 3)["state"] == "online");  // reconnected
    f.adapter->stop();
    CHECK(f.app->wait("Notify/State/test-dev", 4)["state"] == "offline");
    CHECK(f.broker.retained("Notify/State/test-dev")->payload == R"({"state":"offline","tid":"test-dev"})");
}

TEST_CASE("the adapter watches the Notify/State of the applications that talk to it, not every terminal's") {
    // Notify/State/+ would bring every terminal's retained state to every
    // adapter: N x N messages when a plant of N terminals reconnects.
    AdapterFixture f(AdapterConfig{}, false);
    for (int i = 0; i < 20; ++i)
        f.app->send(fmt::format("Notify/State/other-{}", i), fmt::format(R"({{"tid":"other-{}","state":"online"}})", i), true);
    // A stale retained "offline" of the application, from an earlier run of it.
    f.app->send("Notify/State/app", R"({"tid":"app","state":"offline"})", true);
    f.start();
    (void)f.query(Json::array({"pos"}));  // its first DTU: the adapter watches Notify/State/app now
    f.app->send("fixture/after", "x");
    REQUIRE(eventually([&] { return !f.app->on("fixture/after").empty(); }));
    // The retained offline it got on subscribing released nothing.
    CHECK(f.adapter->stats().applications_released == 0);
    const auto in = f.adapter->traffic_stats().dtus_in;
    const auto states = in.count("notify_state") ? in.at("notify_state") : 0;
    CHECK(states <= 1);  // that retained one at most, none of the 20 others
    // A live offline releases it.
    f.app->send("Notify/State/app", R"({"tid":"app","state":"offline"})", true);
    CHECK(eventually([&] { return f.adapter->stats().applications_released == 1; }));
}
