// nclink-bridge as systemd runs it: started on a configuration file, SIGHUP
// re-reads the file (docs/bridge.md "Reload"). log_level applies at once;
// keys that need a restart are named and keep their running value; a broken
// file is refused whole, the running configuration stays and the bridge keeps
// serving. A real process against a real mosquitto.
#include "support/child_process.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string bridge_config(const std::string& broker, const std::string& extra) {
    return "{\n  \"broker\": {\"url\": \"" + broker + "\"},\n  \"http\": \"127.0.0.1:0\",\n  \"shdr_enabled\": false" + extra +
           "\n}\n";
}

}  // namespace

TEST_CASE("nclink-bridge: SIGHUP applies log_level, names what needs a restart and refuses a broken file") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-itest-bridge-reload-");
    fs::create_directories(dir.path);
    const fs::path config = dir.path / "bridge.json";
    write(config, bridge_config(broker.url(), ",\n  \"log_level\": \"info\""));
    ChildProcess bridge({binary_path("nclink-bridge"), "--config", config.string()}, (dir.path / "log").string());
    REQUIRE(bridge.started());
    REQUIRE(eventually([&] { return bridge.count("SIGHUP reloads") == 1; }));
    std::smatch port;
    const std::string started_log = bridge.log();
    REQUIRE(std::regex_search(started_log, port, std::regex(R"(MTConnect on http://127\.0\.0\.1:(\d+)/)")));
    httplib::Client http("127.0.0.1", std::stoi(port[1]));
    http.set_read_timeout(10, 0);

    // warn: from now on no info line; the restart-only key is the sync point
    // (a warning), and its report shows that the level changed with it.
    write(config, bridge_config(broker.url(), ",\n  \"log_level\": \"warn\",\n  \"buffer_size\": 16"));
    bridge.signal(SIGHUP);
    REQUIRE(eventually([&] { return bridge.count("applied only after a restart: buffer_size") == 1; }));
    CHECK(bridge.count("reloaded " + config.string()) == 0);  // "applied log_level" is an info line

    // A broken file: refused whole, with the key named; the bridge serves on.
    write(config, bridge_config(broker.url(), ",\n  \"log_level\": \"debug\",\n  \"buffer_sise\": 16"));
    bridge.signal(SIGHUP);
    REQUIRE(eventually([&] { return bridge.count("reload refused, the running configuration stays") == 1; }));
    CHECK(bridge.count("buffer_sise") >= 1);
    auto probe = http.Get("/probe");
    REQUIRE(probe);
    CHECK(probe->status == 200);

    // The level is still warn (the broken file's debug was not taken): the
    // next reload's info line is not written, its warning is.
    write(config, bridge_config(broker.url(), ",\n  \"log_level\": \"warn\",\n  \"buffer_size\": 16"));
    bridge.signal(SIGHUP);
    REQUIRE(eventually([&] { return bridge.count("applied only after a restart: buffer_size") == 2; }));
    CHECK(bridge.count("reloaded " + config.string()) == 0);

    // Back to info: the reload says so, and nothing else changed.
    write(config, bridge_config(broker.url(), ",\n  \"log_level\": \"info\""));
    bridge.signal(SIGHUP);
    REQUIRE(eventually([&] { return bridge.count("reloaded " + config.string() + ": applied log_level") == 1; }));
    bridge.signal(SIGHUP);
    REQUIRE(eventually([&] { return bridge.count("reloaded " + config.string() + ": nothing changed") == 1; }));
    CHECK(bridge.running());

    bridge.signal(SIGTERM);
    CHECK(bridge.wait_exit(10s) == std::optional<int>(0));
}
