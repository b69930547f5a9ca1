// The agent's configuration through the shared reader: unknown keys with the
// nearest valid key, pointers built from keys that hold '.', '/' or '*', and
// errors located as path:line:column. (The reader itself is tested with the
// core, tests/unit/core/test_config_reader.cpp; the agent is plant-side and
// not part of the terminal library a cross build links.)
#include <nclink/agent.hpp>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace nclink;

TEST_CASE("agent configuration: an unknown top-level key is refused with the nearest key and its pointer") {
    auto top = agent_config_from_json(Json{{"request_timout_ms", 5}});
    REQUIRE_FALSE(top.ok());
    CHECK(top.error().code == ErrorCode::keys_of_arguments);
    CHECK_THAT(top.error().message, Catch::Contains("did you mean \"request_timeout_ms\"?"));
    CHECK(top.error().pointer == "/request_timout_ms");
}

TEST_CASE("agent configuration: wrong values point at their key, also under terminal ids and application names") {
    // A terminal id with a dot and a slash: the pointer is built from the keys.
    auto t = agent_config_from_json(Json{{"registration", {{"terminals", {{"line.3/mill", {{"kind", "robot"}}}}}}}});
    REQUIRE_FALSE(t.ok());
    CHECK(t.error().pointer == "/registration/terminals/line.3~1mill/kind");
    auto rights = agent_config_from_json(Json{{"access", {{"applications", {{"mes", {{"*", "write"}}}}}}}});
    REQUIRE_FALSE(rights.ok());
    CHECK(rights.error().pointer == "/access/applications/mes/*");
    CHECK(agent_config_from_json(Json{{"request_timeout_ms", 0}}).error().pointer == "/request_timeout_ms");
}

TEST_CASE("agent configuration files: a reader error is located as path:line:column") {
    const auto dir = std::filesystem::temp_directory_path() / "nclink-agent-config-reader-test";
    std::filesystem::create_directories(dir);
    const auto typo = (dir / "typo.json").string();
    std::ofstream(typo) << "{\n  \"broker\": {\n    \"uri\": \"tcp://x:1\"\n  }\n}\n";
    auto located = load_agent_config(typo);
    REQUIRE_FALSE(located.ok());
    CHECK_THAT(located.error().message, Catch::StartsWith(typo + ":3:5: configuration: broker.uri: unknown key"));
    CHECK(located.error().pointer == "/broker/uri");
    std::filesystem::remove_all(dir);
}

TEST_CASE("agent configuration: instances and instance split the work only with plain subscriptions") {
    auto plain = agent_config_from_json(Json{{"share_group", ""}, {"instances", 3}, {"instance", 2}});
    REQUIRE(plain.ok());
    CHECK(plain->instances == 3);
    CHECK(plain->instance == 2);
    auto defaults = agent_config_from_json(Json::object());
    REQUIRE(defaults.ok());
    CHECK(defaults->instances == 1);  // one instance answering everything: the agent as before
    CHECK(defaults->instance == 0);

    // The broker's $share already hands each request to one member: splitting again would lose most.
    auto shared = agent_config_from_json(Json{{"instances", 2}});
    REQUIRE_FALSE(shared.ok());
    CHECK(shared.error().code == ErrorCode::out_of_range);
    CHECK(shared.error().pointer == "/instances");
    CHECK_THAT(shared.error().message, Catch::Contains("share_group is set (\"nclink-agent\")"));
    auto numbered = agent_config_from_json(Json{{"share_group", ""}, {"instances", 2}, {"instance", 2}});
    REQUIRE_FALSE(numbered.ok());
    CHECK(numbered.error().code == ErrorCode::out_of_range);
    CHECK(numbered.error().pointer == "/instance");
    CHECK_THAT(numbered.error().message, Catch::Contains("instance must be below instances (2)"));
    auto none = agent_config_from_json(Json{{"share_group", ""}, {"instances", 0}});
    REQUIRE_FALSE(none.ok());
    CHECK(none.error().pointer == "/instances");
    CHECK_THAT(none.error().message, Catch::Contains("instances must be at least 1"));
    CHECK(agent_config_from_json(Json{{"instance", -1}}).error().code == ErrorCode::value_type);
    CHECK(agent_config_from_json(Json{{"instances", "2"}}).error().code == ErrorCode::value_type);
}

TEST_CASE("agent configuration files: a bad instance number is located as path:line:column") {
    const auto dir = std::filesystem::temp_directory_path() / "nclink-agent-config-split-test";
    std::filesystem::create_directories(dir);
    const auto path = (dir / "agent.json").string();
    std::ofstream(path) << "{\n  \"share_group\": \"\",\n  \"instances\": 2,\n  \"instance\": 5\n}\n";
    auto located = load_agent_config(path);
    REQUIRE_FALSE(located.ok());
    CHECK_THAT(located.error().message, Catch::StartsWith(path + ":4:3: configuration: instance must be below instances (2)"));
    std::filesystem::remove_all(dir);
}
