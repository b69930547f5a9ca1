// Changing the model at run time through the SDK (Adapter::replace_model,
// Adapter::patch_model): validated first, swapped, announced (8.2.5.3),
// registrations that no longer resolve answered 401; and which model a
// restart serves when a persisted one meets a newer shipped one.
#include "support/adapter_fixture.hpp"

#include <nclink/model_version.hpp>

#include <fstream>

using namespace nclink;
using namespace nclink::test;

namespace {

Json test_model() { return Json::parse(std::ifstream(test_model_path())); }

/// Moves the fixture's ManualClock on while `body` runs: the sampling engine
/// waits on it when channels are added or removed.
template <class Body>
void with_ticking(AdapterFixture& f, Body&& body) {
    std::atomic<bool> done{false};
    std::thread ticker([&] {
        while (!done) {
            f.clock->advance(std::chrono::milliseconds(20));
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    });
    body();
    done = true;
    ticker.join();
}

Json without_item(Json model, const std::string& id) {
    auto& items = model["devices"][0]["dataItems"];
    for (auto it = items.begin(); it != items.end(); ++it)
        if ((*it)["id"] == id) {
            items.erase(it);
            break;
        }
    return model;
}

}  // namespace

TEST_CASE("replace_model validates, swaps, persists and announces the new version") {
    AdapterFixture f;
    Json model = test_model();
    model["devices"][0]["version"] = "1.1.0";
    model["devices"][0]["dataItems"].push_back(Json{{"id", "temp"}, {"type", "TEMPERATURE"}, {"value", 21.5}});
    (void)f.app->wait("Probe/Version/test-dev");  // the one of the connection, first
    const auto versions = f.app->on("Probe/Version/test-dev").size();
    auto replaced = f.adapter->replace_model(model.dump());
    REQUIRE(replaced.ok());
    CHECK(replaced.value() == "1.1.0");
    CHECK(f.app->wait("Probe/Version/test-dev", versions + 1)["version"] == "1.1.0");
    CHECK(f.adapter->model()->data_object("temp") != nullptr);
    CHECK(f.query(Json::array({Json{{"id", "temp"}}}))["values"][0]["values"] == Json::array({21.5}));
    CHECK(std::filesystem::exists(std::filesystem::path(f.config.persistence_dir) / "model.json"));
}

TEST_CASE("replace_model refuses an invalid model with every problem, and nothing changes") {
    AdapterFixture f;
    Json model = test_model();
    model["devices"][0]["dataItems"].push_back(Json{{"id", "pos"}, {"type", "POSITION"}});  // duplicate id
    model["devices"][0]["configs"][2]["sampleInterval"] = -5;
    (void)f.app->wait("Probe/Version/test-dev");  // the one of the connection, first
    const auto versions = f.app->on("Probe/Version/test-dev").size();
    auto replaced = f.adapter->replace_model(model.dump());
    REQUIRE_FALSE(replaced.ok());
    CHECK(replaced.error().code == ErrorCode::syntax_error);
    CHECK_THAT(replaced.error().message, Catch::Contains("duplicate"));
    CHECK_THAT(replaced.error().message, Catch::Contains("sampleInterval"));
    CHECK_FALSE(f.adapter->replace_model("{not json").ok());
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(f.app->on("Probe/Version/test-dev").size() == versions);
    CHECK(f.adapter->model()->device("dev-1")->version == "1.0.0");
    CHECK_FALSE(std::filesystem::exists(std::filesystem::path(f.config.persistence_dir) / "model.json"));
}

TEST_CASE("patch_model applies a JSON Patch to the current model: a new tool at run time") {
    AdapterFixture f;
    const Json patch = Json::array(
        {Json{{"op", "replace"}, {"path", "/devices/0/version"}, {"value", "1.0.1"}},
         Json{{"op", "add"},
              {"path", "/devices/0/components"},
              {"value",
               Json::array({Json{{"id", "tool1"},
                                 {"type", "COMPONENT"},
                                 {"dataItems", Json::array({Json{{"id", "tool1_len"}, {"type", "LENGTH"}, {"value", 80.0}}})}}})}}});
    auto patched = f.adapter->patch_model(patch);
    INFO((patched.ok() ? std::string() : patched.error().describe()));
    REQUIRE(patched.ok());
    CHECK(patched.value() == "1.0.1");
    CHECK(f.query(Json::array({Json{{"id", "tool1_len"}}}))["values"][0]["values"] == Json::array({80.0}));

    SECTION("a patch that is not an array is 405, one that does not apply 413; nothing changes") {
        auto not_array = f.adapter->patch_model(Json{{"op", "add"}});
        REQUIRE_FALSE(not_array.ok());
        CHECK(not_array.error().code == ErrorCode::value_type);
        auto bad_path = f.adapter->patch_model(Json::array({Json{{"op", "remove"}, {"path", "/devices/7/dataItems/0"}}}));
        REQUIRE_FALSE(bad_path.ok());
        CHECK(bad_path.error().code == ErrorCode::keys_of_arguments);
        auto failed_test =
            f.adapter->patch_model(Json::array({Json{{"op", "test"}, {"path", "/devices/0/version"}, {"value", "9.9.9"}}}));
        REQUIRE_FALSE(failed_test.ok());
        CHECK(f.adapter->model()->device("dev-1")->version == "1.0.1");
    }
}

TEST_CASE("a model change releases registrations that no longer resolve and tells their owners 401") {
    AdapterFixture f;
    const Json event =
        f.app->request(topics::event_register_request("test-dev", "app"), topics::event_register_response("test-dev", "app"),
                       Json{{"@id", "e1"}, {"guid", "test-dev"}, {"id", "ovr"}, {"triggerType", "always"}});
    REQUIRE(event["code"] == "OK");
    const std::string event_id = event["id"];
    Json channel;
    with_ticking(f, [&] {
        channel = f.app->request(topics::sample_register_request("test-dev", "app"),
                                 topics::sample_register_response("test-dev", "app"),
                                 Json{{"@id", "s1"},
                                      {"guid", "test-dev"},
                                      {"sampleInterval", 10},
                                      {"uploadInterval", 100},
                                      {"ids", Json::array({Json{{"id", "ovr"}}})}});
    });
    REQUIRE(channel["code"] == "OK");
    const std::string channel_id = channel["id"];

    Json model = without_item(test_model(), "ovr");
    model["devices"][0]["version"] = "1.2.0";
    with_ticking(f, [&] { REQUIRE(f.adapter->replace_model(model.dump()).ok()); });

    const Json event_gone = f.app->wait(topics::event_register_response("test-dev", "app"), 2);
    CHECK(event_gone["code"] == "NG");
    CHECK(event_gone["error"] == 401);
    CHECK(event_gone["reason"] == "Node not exists");
    CHECK(event_gone["id"] == event_id);
    const Json channel_gone = f.app->wait(topics::sample_register_response("test-dev", "app"), 2);
    CHECK(channel_gone["code"] == "NG");
    CHECK(channel_gone["error"] == 401);
    CHECK(channel_gone["id"] == channel_id);
    // Gone on the adapter too: unregistering them now is 401.
    const Json unregister =
        f.app->request(topics::event_unregister_request("test-dev", "app"), topics::event_unregister_response("test-dev", "app"),
                       Json{{"@id", "u1"}, {"guid", "test-dev"}, {"id", event_id}});
    CHECK(unregister["error"] == 401);
}

TEST_CASE("a restart serves the shipped model when it is newer than the persisted one, and says so") {
    // Declared before the fixture: its adapter still logs while it stops.
    std::vector<std::string> lines;
    std::mutex mutex;
    AdapterFixture f;
    Json persisted = test_model();
    persisted["devices"][0]["version"] = "1.1.0";
    REQUIRE(f.adapter->replace_model(persisted.dump()).ok());
    f.adapter->stop();
    f.adapter.reset();

    const std::string shipped_path = (std::filesystem::path(f.config.persistence_dir) / "shipped.json").string();
    Json shipped = test_model();
    f.config.model_path = shipped_path;
    f.logger = Logger([&](LogLevel, std::string_view line) {
        std::lock_guard<std::mutex> lock(mutex);
        lines.emplace_back(line);
    });
    auto said = [&](const std::string& text) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& l : lines)
            if (l.find(text) != std::string::npos) return true;
        return false;
    };

    SECTION("shipped older than persisted: the persisted model stays") {
        shipped["devices"][0]["version"] = "1.0.9";
        std::ofstream(shipped_path) << shipped.dump();
        f.start();
        CHECK(f.adapter->model()->device("dev-1")->version == "1.1.0");
        CHECK(said("using the persisted model"));
    }
    SECTION("shipped newer (a firmware update): the shipped model wins") {
        shipped["devices"][0]["version"] = "1.2.0";
        std::ofstream(shipped_path) << shipped.dump();
        f.start();
        CHECK(f.adapter->model()->device("dev-1")->version == "1.2.0");
        CHECK(said("using the shipped model"));
        CHECK_FALSE(std::filesystem::exists(std::filesystem::path(f.config.persistence_dir) / "model.json"));
    }
}

TEST_CASE("model version order (chapter 6 form, with the standard's 'v1.0.1' and '1.3' spellings)") {
    CHECK(compare_model_versions("1.0.0", "1.0.1") == -1);
    CHECK(compare_model_versions("1.3", "1.3.0") == 0);
    CHECK(compare_model_versions("v1.0.10", "1.0.9") == 1);
    CHECK_FALSE(compare_model_versions("1.x", "1.0").has_value());
    CHECK(is_model_version("v1.0.1"));
    CHECK_FALSE(is_model_version("1..0"));
    CHECK(next_model_version("1.0.9") == "1.0.10");
    CHECK(next_model_version("v1.3") == "v1.4");
}
