// The shared configuration reader: unknown keys with the nearest valid key,
// errors that carry a JSON pointer, and locating a pointer (or a syntax
// error) by line and column in the file's text.
#include <nclink/adapter_config.hpp>
#include <nclink/log.hpp>

#include "core/config_common.hpp"
#include "core/config_reader.hpp"
#include "core/json_locate.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>

using namespace nclink;
using namespace nclink::core_detail;

namespace {

std::string scratch_file(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "nclink-config-reader-test";
    std::filesystem::create_directories(dir);
    const auto path = dir / name;
    std::ofstream(path) << text;
    return path.string();
}

}  // namespace

TEST_CASE("nearest key: typos, other spellings and words inside a key are found") {
    const std::vector<std::string> broker = {"url", "client_id", "username", "password", "mqtt_version", "keep_alive_s", "tls"};
    CHECK(nearest_key("uri", broker) == std::optional<std::string>("url"));
    CHECK(nearest_key("keep_alive", broker) == std::optional<std::string>("keep_alive_s"));
    CHECK(nearest_key("keepAliveS", broker) == std::optional<std::string>("keep_alive_s"));
    CHECK(nearest_key("client-id", broker) == std::optional<std::string>("client_id"));
    CHECK(nearest_key("usrename", broker) == std::optional<std::string>("username"));
    CHECK(nearest_key("version", broker) == std::optional<std::string>("mqtt_version"));
    CHECK_FALSE(nearest_key("colour", broker).has_value());
    CHECK_FALSE(nearest_key("x", broker).has_value());
    CHECK_FALSE(nearest_key("", broker).has_value());
    CHECK_FALSE(nearest_key("uri", {}).has_value());
}

TEST_CASE("config reader: an unknown key is refused with a suggestion the valid keys and a pointer") {
    auto r = adapter_config_from_json(Json::parse(R"({"broker": {"uri": "tcp://x:1"}})"));
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::keys_of_arguments);
    CHECK_THAT(r.error().message, Catch::StartsWith("configuration: broker.uri: unknown key; did you mean \"url\"?"));
    CHECK_THAT(r.error().message, Catch::Contains("valid keys: url, client_id"));
    CHECK(r.error().pointer == "/broker/uri");

    auto none = adapter_config_from_json(Json{{"zzzzzz", 1}});
    REQUIRE_FALSE(none.ok());
    CHECK_THAT(none.error().message, !Catch::Contains("did you mean"));
}

TEST_CASE("config reader: wrong types and values point at their key, also in nested and dotted sections") {
    CHECK(adapter_config_from_json(Json{{"sampling", {{"qos", 2}}}}).error().pointer == "/sampling/qos");
    CHECK(adapter_config_from_json(Json{{"broker", {{"tls", {{"verify", "yes"}}}}}}).error().pointer == "/broker/tls/verify");
    CHECK(adapter_config_from_json(Json{{"broker", {{"mqtt_version", 3}}}}).error().pointer == "/broker/mqtt_version");
    CHECK(adapter_config_from_json(Json{{"log_level", "loud"}}).error().pointer == "/log_level");
    CHECK(adapter_config_from_json(Json{{"methods", 5}}).error().pointer == "/methods");
    CHECK(adapter_config_from_json(Json{{"methods", 5}}).error().message == "configuration: methods must be an object");
}

TEST_CASE("config reader: a count past the range of its type is refused, never cut") {
    const Json section = Json::parse(R"({"big": 5000000000, "fits": 4294967295, "negative": -1})");
    ConfigReader reader(section, "limits.");
    std::uint32_t big = 7, fits = 0, negative = 0;
    const auto r = reader.count("big", big);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::value_type);
    CHECK(r.error().message == "configuration: limits.big must be at most 4294967295");
    CHECK(r.error().pointer == "/limits/big");
    CHECK(big == 7);  // left as it was, not 705032704
    CHECK(reader.count("fits", fits).ok());
    CHECK(fits == 4294967295u);
    CHECK_FALSE(reader.count("negative", negative).ok());
    CHECK(reader.no_unknown_keys().ok());  // refused keys were read, not unknown

    // A byte limit of 5 GB: kept on a 64-bit target, refused with its key on
    // a 32-bit one (armhf: size_t is 32 bits), where it was cut before.
    const auto cfg = adapter_config_from_json(Json{{"offline_buffer_bytes", 5'000'000'000ULL}});
    if (sizeof(std::size_t) < 8) {
        REQUIRE_FALSE(cfg.ok());
        CHECK(cfg.error().pointer == "/offline_buffer_bytes");
        CHECK_THAT(cfg.error().message, Catch::Contains("must be at most 4294967295"));
    } else {
        REQUIRE(cfg.ok());
        CHECK(cfg.value().offline_buffer_bytes == 5'000'000'000ULL);
    }
}

TEST_CASE("pointers: appended keys are escaped and dotted sections map to pointers") {
    CHECK(pointer_append("/a", "b/c~d") == "/a/b~1c~0d");
    CHECK(pointer_of_where("broker.tls.") == "/broker/tls");
    CHECK(pointer_of_where("") == "");
}

TEST_CASE("locate: a pointer is found by line and column in the text") {
    const std::string text =
        "{\n  \"broker\": {\"url\": \"x\",\n    \"tls\": {\"verify\": true}},\n  \"a~b\": [10, {\"k\": 1}],\n  \"é\": 1, \"z\": "
        "2\n}";
    auto at = [&](const char* p) {
        auto pos = locate_pointer(text, p);
        return pos ? std::to_string(pos->line) + ":" + std::to_string(pos->column) : std::string("none");
    };
    CHECK(at("") == "1:1");
    CHECK(at("/broker") == "2:3");
    CHECK(at("/broker/url") == "2:14");
    CHECK(at("/broker/tls/verify") == "3:13");
    CHECK(at("/a~0b/1/k") == "4:16");
    CHECK(at("/a~0b/0") == "4:11");
    CHECK(at("/z") == "5:11");  // columns count characters, not bytes
    CHECK(at("/nope") == "none");
    CHECK(at("/a~0b/7") == "none");
    CHECK(at("/broker/url/deeper") == "none");
    CHECK(at("no-slash") == "none");
    // The last of duplicate keys counts, as when parsing.
    CHECK(locate_pointer("{\"a\": 1,\n \"a\": 2}", "/a")->line == 2);
    // Escapes in keys are decoded before comparing.
    CHECK(locate_pointer(R"({"\u0041\n": 1})", "/A\n").has_value());
}

TEST_CASE("configuration files: syntax errors and reader errors are located as path:line:column") {
    const auto broken = scratch_file("broken.json", "{\n  \"model\": \"m.json\",\n}\n");
    auto syntax = load_adapter_config(broken);
    REQUIRE_FALSE(syntax.ok());
    CHECK(syntax.error().code == ErrorCode::syntax_error);
    CHECK_THAT(syntax.error().message, Catch::StartsWith(broken + ":3:1: not valid JSON"));

    const auto typo = scratch_file("typo.json", "{\n  \"broker\": {\n    \"uri\": \"tcp://x:1\"\n  }\n}\n");
    auto located = load_adapter_config(typo);
    REQUIRE_FALSE(located.ok());
    CHECK_THAT(located.error().message, Catch::StartsWith(typo + ":3:5: configuration: broker.uri: unknown key"));
    CHECK(located.error().pointer == "/broker/uri");

    const auto not_object = scratch_file("array.json", "[1]");
    CHECK_THAT(load_adapter_config(not_object).error().message, Catch::StartsWith(not_object + ": configuration:"));
    std::filesystem::remove_all(std::filesystem::path(broken).parent_path());
}

TEST_CASE("logger: set_min_level changes every copy of a logger") {
    int seen = 0;
    const Logger a([&](LogLevel, std::string_view) { ++seen; }, LogLevel::error);
    const Logger b = a;
    b.info("hidden");
    CHECK(seen == 0);
    a.set_min_level(LogLevel::info);
    CHECK(b.min_level() == LogLevel::info);
    b.info("shown");
    CHECK(seen == 1);
    Logger silent;
    silent.set_min_level(LogLevel::trace);  // a logger without a sink stays silent
    CHECK_FALSE(silent.enabled(LogLevel::error));
}
