// The service programs as systemd runs them: nclink-agent and nclink-sim
// started on a configuration file, reloaded with SIGHUP, stopped with
// SIGTERM, against a real mosquitto. A broken file at start stops the
// program with one located line before anything is written; a broken file at
// reload is refused and the program keeps serving on its running rules.
#include <nclink/client.hpp>

#include "support/child_process.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <csignal>
#include <set>
#include <filesystem>
#include <fstream>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::size_t lines_of(const std::string& text) { return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')); }

std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        names.insert(e.path().string() + " " + std::to_string(e.is_regular_file() ? fs::file_size(e.path()) : 0));
    return names;
}

RegisterOutcome::Kind registration_of(const std::string& broker, const std::string& ex) {
    auto client = started_client(broker, ex, 5s);
    auto outcome = client->register_terminal();
    client->stop();
    REQUIRE(outcome.ok());
    return outcome->kind;
}

std::string agent_config(const std::string& broker, const fs::path& state, const std::string& extra) {
    return "{\n  \"broker\": {\"url\": \"" + broker + "\"},\n  \"state_dir\": \"" + state.string() +
           "\",\n  \"log_level\": \"info\"" + extra + "\n}\n";
}

}  // namespace

TEST_CASE("nclink-agent: a broken configuration stops the start with one located line and writes nothing") {
    ScratchDir dir("nclink-itest-ops-");
    fs::create_directories(dir.path);
    const fs::path state = dir.path / "state";
    fs::create_directories(state);
    write(state / "registry.json", "{\"kept\": true}");
    const fs::path config = dir.path / "agent.json";
    write(config, "{\n  \"state_dir\": \"" + state.string() + "\",\n  \"broker\": {\n    \"uri\": \"tcp://127.0.0.1:1\"}\n}\n");
    const auto before = listing(dir.path);
    ChildProcess agent({binary_path("nclink-agent"), "--config", config.string()}, (dir.path / "log").string());
    REQUIRE(agent.started());
    CHECK(agent.wait_exit(10s) == std::optional<int>(2));
    const std::string log = agent.log();
    CHECK(lines_of(log) == 1);
    CHECK_THAT(log, Catch::StartsWith("nclink-agent: " + config.string() +
                                      ":4:5: configuration: broker.uri: unknown key; did you mean \"url\"?"));
    fs::remove(dir.path / "log");
    CHECK(listing(dir.path) == before);

    write(config, "{\n  \"state_dir\": \"x\",,\n}\n");
    ChildProcess syntax({binary_path("nclink-agent"), "--config", config.string()}, (dir.path / "log2").string());
    CHECK(syntax.wait_exit(10s) == std::optional<int>(2));
    CHECK_THAT(syntax.log(), Catch::Contains(config.string() + ":2:20: not valid JSON"));

    ChildProcess check({binary_path("nclink-agent"), "--config", config.string(), "--check-config"}, (dir.path / "log3").string());
    CHECK(check.wait_exit(10s) == std::optional<int>(2));
}

TEST_CASE("nclink-agent: SIGHUP applies a new allowlist, refuses a broken file and keeps serving") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-itest-ops-");
    fs::create_directories(dir.path);
    const fs::path config = dir.path / "agent.json";
    const fs::path state = dir.path / "state";
    write(config, agent_config(broker.url(), state, ""));
    ChildProcess agent({binary_path("nclink-agent"), "--config", config.string()}, (dir.path / "log").string());
    REQUIRE(eventually([&] { return agent.count("serving on") == 1; }));
    REQUIRE(registration_of(broker.url(), "mes-1") == RegisterOutcome::Kind::accepted);

    write(config,
          agent_config(broker.url(), state,
                       ",\n  \"registration\": {\"open\": false, \"terminals\": {\"mes-1\": {\"kind\": \"application\"}}}"));
    agent.signal(SIGHUP);
    REQUIRE(eventually([&] { return agent.count("applied registration") == 1; }));
    CHECK(registration_of(broker.url(), "stranger") == RegisterOutcome::Kind::refused);

    // A broken file: refused with its place, the running rules stay.
    write(config, "{\n  \"registration\": {\"open\": true,\n  \"log_level\": \"debug\"\n}\n");
    agent.signal(SIGHUP);
    REQUIRE(eventually([&] { return agent.count("reload refused") == 1; }));
    CHECK_THAT(agent.log(),
               Catch::Contains("reload refused, the running configuration stays: " + config.string() + ":5:1: not valid JSON"));
    CHECK(registration_of(broker.url(), "stranger-2") == RegisterOutcome::Kind::refused);
    CHECK(registration_of(broker.url(), "mes-1") == RegisterOutcome::Kind::accepted);

    // Keys that need a restart are named and left alone; the rest applies.
    write(config, "{\n  \"broker\": {\"url\": \"tcp://127.0.0.1:1\"},\n  \"state_dir\": \"" + state.string() +
                      "\",\n  \"log_level\": \"debug\"\n}\n");
    agent.signal(SIGHUP);
    REQUIRE(eventually([&] { return agent.count("applied only after a restart: broker.url") == 1; }));
    CHECK(agent.count("applied registration, log_level") == 1);
    CHECK(registration_of(broker.url(), "stranger-3") == RegisterOutcome::Kind::accepted);  // open again

    agent.signal(SIGTERM);
    CHECK(agent.wait_exit(10s) == std::optional<int>(0));
}

TEST_CASE("nclink-sim: SIGHUP applies log_level, names what needs a restart and refuses a broken file") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-itest-ops-");
    fs::create_directories(dir.path);
    const fs::path config = dir.path / "sim.json";
    const std::string base = "{\n  \"broker\": {\"url\": \"" + broker.url() + "\"},\n  \"register_timeout_ms\": 200";
    write(config, base + "\n}\n");
    ChildProcess sim({binary_path("nclink-sim"), "--config", config.string()}, (dir.path / "log").string());
    REQUIRE(eventually([&] { return sim.count("answering as") == 1; }));

    write(config, base + ",\n  \"log_level\": \"debug\"\n}\n");
    sim.signal(SIGHUP);
    REQUIRE(eventually([&] { return sim.count("reloaded " + config.string() + ": applied log_level") == 1; }));

    write(config, base + ",\n  \"log_level\": \"debug\", \"dedup_capacity\": 7\n}\n");
    sim.signal(SIGHUP);
    REQUIRE(eventually([&] { return sim.count("applied only after a restart: dedup_capacity") == 1; }));

    write(config, base + ",\n  \"log_levl\": \"warn\"\n}\n");
    sim.signal(SIGHUP);
    REQUIRE(eventually([&] { return sim.count("reload refused") == 1; }));
    CHECK_THAT(sim.log(),
               Catch::Contains(config.string() + ":4:3: configuration: log_levl: unknown key; did you mean \"log_level\"?"));

    sim.signal(SIGTERM);
    CHECK(sim.wait_exit(10s) == std::optional<int>(0));

    ChildProcess broken({binary_path("nclink-sim"), "--config", config.string()}, (dir.path / "log2").string());
    CHECK(broken.wait_exit(10s) == std::optional<int>(2));
    CHECK(lines_of(broken.log()) == 1);
}

TEST_CASE("nclink-sim --machines and --gateway: SIGHUP touches only the machines the file changed") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-itest-ops-gw-");
    fs::create_directories(dir.path);

    // --machines N on a --config: a log level applies to every machine in place.
    const fs::path config = dir.path / "sim.json";
    const std::string base = "{\n  \"broker\": {\"url\": \"" + broker.url() + "\"},\n  \"register_timeout_ms\": 200";
    write(config, base + "\n}\n");
    ChildProcess fleet({binary_path("nclink-sim"), "--machines", "2", "--config", config.string()},
                       (dir.path / "fleet.log").string());
    REQUIRE(eventually([&] { return fleet.count("nclink-sim: 2 machine(s) serving") == 1; }, 30s));
    write(config, base + ",\n  \"log_level\": \"debug\"\n}\n");
    fleet.signal(SIGHUP);
    REQUIRE(eventually([&] { return fleet.count("applied in place [sim-0000, sim-0001]") == 1; }, 20s));
    write(config, base + ",\n  \"log_levl\": \"warn\"\n}\n");
    fleet.signal(SIGHUP);
    REQUIRE(eventually([&] { return fleet.count("machines keep running as they were") == 1; }, 20s));
    fleet.signal(SIGTERM);
    CHECK(fleet.wait_exit(10s) == std::optional<int>(0));

    // --gateway FILE: one machine removed, one added, one changed; the fourth untouched.
    const fs::path gateway = dir.path / "gateway.json";
    auto machine = [](const std::string& guid, const std::string& extra = "") {
        return "{\"dev_uuid\": \"" + guid + "\", \"model\": \"" + sim_mill_path() + "\"" + extra + "}";
    };
    auto write_gateway = [&](const std::vector<std::string>& machines) {
        std::string list;
        for (const auto& m : machines) list += (list.empty() ? "" : ",\n    ") + m;
        write(gateway, "{\n  \"defaults\": {\"broker\": {\"url\": \"" + broker.url() +
                           "\"}, \"register_timeout_ms\": 200},\n  \"machines\": [\n    " + list + "\n  ]\n}\n");
    };
    write_gateway({machine("gw-a"), machine("gw-b"), machine("gw-c")});
    ChildProcess gw({binary_path("nclink-sim"), "--gateway", gateway.string()}, (dir.path / "gw.log").string());
    REQUIRE(eventually([&] { return gw.count("nclink-sim: 3 machine(s) serving") == 1; }, 30s));
    auto client = started_client(broker.url(), "gw-ops-app", 5s);
    auto answers = [&](const std::string& guid) {
        auto values = client->query(guid, {QueryItem{"x_position", std::nullopt}});
        return values.ok() && values->size() == 1 && (*values)[0].status.ok;
    };
    REQUIRE(eventually([&] { return answers("gw-a") && answers("gw-b") && answers("gw-c"); }, 20s));

    write_gateway({machine("gw-a"), machine("gw-c", ", \"dedup_capacity\": 7"), machine("gw-d")});
    gw.signal(SIGHUP);
    REQUIRE(eventually([&] { return gw.count("added [gw-d], removed [gw-b], restarted [gw-c], applied in place []") == 1; }, 30s));
    CHECK(gw.count("machine gw-a removed") == 0);
    CHECK(eventually([&] { return answers("gw-a") && answers("gw-c") && answers("gw-d"); }, 20s));
    CHECK_FALSE(answers("gw-b"));
    client->stop();
    gw.signal(SIGTERM);
    CHECK(gw.wait_exit(10s) == std::optional<int>(0));
}
