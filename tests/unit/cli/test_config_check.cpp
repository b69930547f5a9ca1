// `nclink config check`: every problem of a file, located, with the kind told
// from the content when not given.
#include "config_check.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::cli;

namespace {

std::string where(const ConfigProblem& p) { return std::to_string(p.line) + ":" + std::to_string(p.column); }

}  // namespace

TEST_CASE("config check: every problem is listed in file order with line column and pointer") {
    const std::string text =
        "{\n"
        "  \"agent_id\": \"a\",\n"
        "  \"request_timout_ms\": 10,\n"
        "  \"broker\": {\"uri\": \"tcp://x:1883\", \"keep_alive_s\": -1},\n"
        "  \"access\": {\"default\": [\"read\", \"writ\"]}\n"
        "}\n";
    const ConfigCheck check = check_config_text(text, nullptr);
    REQUIRE(check.kind != nullptr);
    CHECK(std::string(check.kind->name) == "agent");
    CHECK(check.kind_guessed);
    REQUIRE(check.problems.size() == 4);
    CHECK(where(check.problems[0]) == "3:3");
    CHECK(check.problems[0].pointer == "/request_timout_ms");
    CHECK_THAT(check.problems[0].message,
               Catch::StartsWith("request_timout_ms: unknown key; did you mean \"request_timeout_ms\"?"));
    CHECK(where(check.problems[1]) == "4:14");
    CHECK_THAT(check.problems[1].message, Catch::StartsWith("broker.uri: unknown key; did you mean \"url\"?"));
    CHECK(where(check.problems[2]) == "4:37");
    CHECK(check.problems[2].message == "broker.keep_alive_s must be a non-negative integer");
    CHECK(check.problems[3].pointer == "/access/default");
    CHECK(check.problems[3].code == ErrorCode::value_type);
    CHECK_FALSE(check.ok());
}

TEST_CASE("config check: a bad failover entry is located at the entry, and the problems after it are listed too") {
    const std::string text =
        "{\n"
        "  \"broker\": {\"url\": \"tcp://a.plant:1883\",\n"
        "             \"failover\": [\"b.plant:1883\", \"b.plant:x\"]},\n"
        "  \"modle\": \"m.json\"\n"
        "}\n";
    const ConfigCheck check = check_config_text(text, find_config_kind("adapter"));
    REQUIRE(check.problems.size() == 2);
    CHECK(check.problems[0].pointer == "/broker/failover/1");
    CHECK(where(check.problems[0]) == "3:43");
    CHECK(check.problems[0].code == ErrorCode::value_type);
    CHECK_THAT(check.problems[0].message, Catch::StartsWith("broker.failover[1]: unusable broker URL 'tcp://b.plant:x'"));
    CHECK(check.problems[1].pointer == "/modle");
}

TEST_CASE("config check: an agent's unusable instances and instance are both located") {
    // instances 2 with the default share group, and an instance number out of range.
    const std::string text =
        "{\n"
        "  \"agent_id\": \"a\",\n"
        "  \"instances\": 2,\n"
        "  \"instance\": 2\n"
        "}\n";
    const ConfigCheck check = check_config_text(text, find_config_kind("agent"));
    REQUIRE(check.problems.size() == 2);
    CHECK(check.problems[0].pointer == "/instances");
    CHECK(where(check.problems[0]) == "3:3");
    CHECK(check.problems[0].code == ErrorCode::out_of_range);
    CHECK_THAT(check.problems[0].message, Catch::StartsWith("instances must be 1 while share_group is set"));
    CHECK(check.problems[1].pointer == "/instance");
    CHECK(where(check.problems[1]) == "4:3");
    CHECK_THAT(check.problems[1].message, Catch::StartsWith("instance must be below instances (2)"));
}

TEST_CASE("config check: malformed JSON is located at the offending character") {
    const ConfigCheck check = check_config_text("{\n  \"broker\": {\"url\": \"x\",},\n  \"model\": \"m\"\n}\n", nullptr);
    REQUIRE(check.problems.size() == 1);
    CHECK(where(check.problems[0]) == "2:25");
    CHECK(check.problems[0].code == ErrorCode::syntax_error);
    CHECK_THAT(check.problems[0].message, Catch::StartsWith("not valid JSON"));
    CHECK(check_config_text("", find_config_kind("agent")).problems.size() == 1);
    CHECK(check_config_text("{\"a\": 1", find_config_kind("agent")).problems[0].line == 1);
}

TEST_CASE("config check: the kind is told from the keys or asked for") {
    std::string why;
    CHECK(std::string(guess_config_kind(Json{{"model", "m.json"}, {"broker", Json::object()}}, why)->name) == "adapter");
    CHECK(std::string(guess_config_kind(Json{{"share_group", "g"}}, why)->name) == "agent");
    // A typo does not hide the kind: most keys known wins.
    CHECK(std::string(guess_config_kind(Json{{"model", "m"}, {"strict", true}, {"modle", 1}}, why)->name) == "adapter");
    CHECK(guess_config_kind(Json{{"log_level", "info"}}, why) == nullptr);
    CHECK_THAT(why, Catch::Contains("give --kind"));
    CHECK(guess_config_kind(Json{{"nothing", 1}}, why) == nullptr);
    CHECK(guess_config_kind(Json::array(), why) == nullptr);

    const ConfigCheck undecided = check_config_text("{\"log_level\": \"info\"}", nullptr);
    CHECK(undecided.kind == nullptr);
    CHECK_FALSE(undecided.undecided.empty());
    CHECK(undecided.problems.empty());
    CHECK(check_config_text("{\"log_level\": \"info\"}", find_config_kind("adapter")).ok());
    const ConfigCheck array = check_config_text("[1, 2]", nullptr);
    REQUIRE(array.problems.size() == 1);
    CHECK(array.problems[0].message == "the file must hold a JSON object");
}

TEST_CASE("config check: a valid file of either kind passes") {
    CHECK(check_config_text(R"({"model": "m.json", "sampling": {"qos": 1}, "driver": {"config": {"x": [1]}}})", nullptr).ok());
    CHECK(check_config_text(R"({"state_dir": "/var/lib/nclink", "access": {"default": "all"}})", find_config_kind("agent")).ok());
    CHECK(find_config_kind("bridge-of-tomorrow") == nullptr);
}

TEST_CASE("config check: bridge and gateway files, a machine's problem located in its entry") {
    std::string why;
    CHECK(std::string(guess_config_kind(Json{{"http", "127.0.0.1:5000"}, {"devices", Json::array()}}, why)->name) == "bridge");
    CHECK(std::string(guess_config_kind(Json{{"machines", Json::array()}}, why)->name) == "gateway");
    CHECK(check_config_text(R"({"http": "0.0.0.0:5000", "log_level": "warn"})", find_config_kind("bridge")).ok());
    const ConfigCheck bridge = check_config_text("{\n  \"http\": \"nocolon\"\n}\n", find_config_kind("bridge"));
    REQUIRE(bridge.problems.size() == 1);
    CHECK_THAT(bridge.problems[0].message, Catch::Contains("'nocolon' is not HOST:PORT"));

    const std::string text =
        "{\n"
        "  \"defaults\": {\"broker\": {\"url\": \"tcp://10.0.0.5:1883\"}},\n"
        "  \"machines\": [\n"
        "    {\"id\": \"mill-1\", \"model\": \"m.json\"},\n"
        "    {\"id\": \"mill-2\", \"modle\": \"m.json\"}\n"
        "  ]\n"
        "}\n";
    const ConfigCheck gateway = check_config_text(text, nullptr);
    REQUIRE(gateway.kind != nullptr);
    CHECK(std::string(gateway.kind->name) == "gateway");
    REQUIRE(gateway.problems.size() == 1);
    CHECK(gateway.problems[0].pointer == "/machines/1/modle");
    CHECK(where(gateway.problems[0]) == "5:22");
    CHECK_THAT(gateway.problems[0].message, Catch::StartsWith("machines[1]: configuration: modle: unknown key"));
}
