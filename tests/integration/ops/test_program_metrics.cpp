// /metrics of the programs as processes: nclink-agent --metrics and
// nclink-sim --metrics (the adapter's, opt-in), scraped by a real HTTP client
// and checked as Prometheus text; a port beyond loopback is refused without
// credentials before anything starts.
#include "support/child_process.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/prometheus_check.hpp"
#include "support/raw_peer.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// The port a program logged ("metrics on http://127.0.0.1:PORT/metrics").
int logged_port(const ChildProcess& program) {
    std::smatch m;
    const std::string log = program.log();
    if (std::regex_search(log, m, std::regex("metrics on http://127\\.0\\.0\\.1:([0-9]+)/metrics"))) return std::stoi(m[1]);
    return 0;
}

void check_exposition(const std::string& text) {
    INFO(text);
    const auto problems = exposition_problems(text);
    for (const auto& p : problems) UNSCOPED_INFO(p);
    CHECK(problems.empty());
    if (const auto said = promtool_problems(text)) {
        INFO("promtool: " << *said);
        CHECK(said->empty());
    } else {
        WARN("promtool not installed (Debian package prometheus): checked by the test's own reader only");
    }
}

// The "metrics" section of a program's --config reaches its /metrics server:
// with a per-peer cap of 2 the third connection from one address is closed
// at once, and the program's own /metrics counts it.
void per_peer_cap_applies(int port, const std::string& prefix) {
    std::vector<std::unique_ptr<RawPeer>> peers;
    for (int i = 0; i < 3; ++i) peers.push_back(std::make_unique<RawPeer>(port, "127.0.7.1"));
    CHECK(peers[2]->closed_within(5s));
    CHECK_FALSE(peers[0]->closed_within(200ms));
    httplib::Client http("127.0.0.1", port);
    auto r = http.Get("/metrics");
    REQUIRE(r);
    REQUIRE(r->status == 200);
    std::vector<PromSample> samples;
    (void)exposition_problems(r->body, &samples);
    CHECK(prom_value(samples, prefix + "_http_connections_refused_total", {{"cap", "per_peer"}}) == 1.0);
    CHECK(prom_value(samples, prefix + "_http_connections_accepted_total").value_or(0) >= 3.0);
}

}  // namespace

TEST_CASE("the metrics section of --config sets the HTTP limits of nclink-agent's and nclink-sim's /metrics") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-itest-ops-metrics-");
    fs::create_directories(dir.path);
    const std::string config = (dir.path / "config.json").string();
    std::ofstream(config) << R"({"metrics": {"http_max_connections_per_peer": 2}})";

    ChildProcess agent({binary_path("nclink-agent"), "--broker", broker.url(), "--config", config, "--state-dir",
                        (dir.path / "state").string(), "--metrics", "127.0.0.1:0"},
                       (dir.path / "agent.log").string());
    REQUIRE(eventually([&] { return logged_port(agent) > 0; }, 30s));
    per_peer_cap_applies(logged_port(agent), "nclink_agent");
    agent.signal(SIGTERM);
    CHECK(agent.wait_exit(10s) == std::optional<int>(0));

    ChildProcess sim({binary_path("nclink-sim"), "--broker", broker.url(), "--config", config, "--metrics", "127.0.0.1:0"},
                     (dir.path / "sim.log").string());
    REQUIRE(eventually([&] { return logged_port(sim) > 0; }, 30s));
    per_peer_cap_applies(logged_port(sim), "nclink_adapter");
    sim.signal(SIGTERM);
    CHECK(sim.wait_exit(10s) == std::optional<int>(0));
}

TEST_CASE("nclink-agent --metrics serves its counters as Prometheus text on loopback") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-itest-ops-metrics-");
    fs::create_directories(dir.path);
    ChildProcess agent({binary_path("nclink-agent"), "--broker", broker.url(), "--state-dir", (dir.path / "state").string(),
                        "--metrics", "127.0.0.1:0"},
                       (dir.path / "agent.log").string());
    REQUIRE(eventually([&] { return agent.count("serving on") == 1 && logged_port(agent) > 0; }, 30s));
    auto client = started_client(broker.url(), "mes-1", 5s);
    // "serving on" may be logged before the broker has the agent's
    // subscriptions on a loaded machine: a Register/Request sent that early
    // goes unanswered, so it is asked again (the agent accepts a repeat).
    // (No answer is the outcome no_answer, not an error: accepted is asked for.)
    REQUIRE(eventually(
        [&] {
            auto outcome = client->register_terminal();
            return outcome && outcome->kind == RegisterOutcome::Kind::accepted;
        },
        30s));
    httplib::Client http("127.0.0.1", logged_port(agent));
    std::vector<PromSample> samples;
    std::string text;
    REQUIRE(eventually(
        [&] {
            auto r = http.Get("/metrics");
            if (!r || r->status != 200) return false;
            text = r->body;
            samples.clear();
            (void)exposition_problems(text, &samples);
            return prom_value(samples, "nclink_agent_registrations_total", {{"outcome", "accepted"}}).value_or(0) >= 1.0;
        },
        20s));
    check_exposition(text);
    CHECK(prom_value(samples, "nclink_agent_dtus_received_total", {{"kind", "register_request"}}) >= 1.0);
    CHECK(http.Post("/metrics", "x", "text/plain")->status == 405);
    CHECK(http.Get("/other")->status == 404);
    client->stop();
    agent.signal(SIGTERM);
    CHECK(agent.wait_exit(10s) == std::optional<int>(0));

    // Beyond loopback without credentials: refused before the agent starts.
    ChildProcess open({binary_path("nclink-agent"), "--broker", broker.url(), "--state-dir", (dir.path / "state2").string(),
                       "--metrics", "0.0.0.0:0"},
                      (dir.path / "open.log").string());
    CHECK(open.wait_exit(10s) == std::optional<int>(1));
    CHECK_THAT(open.log(), Catch::Contains("loopback"));
    CHECK(open.count("serving on") == 0);
}

TEST_CASE("nclink-sim --metrics serves the adapter's metrics, which are off by default") {
    MosquittoBroker broker;
    ScratchDir dir("nclink-itest-ops-metrics-");
    fs::create_directories(dir.path);
    ChildProcess plain({binary_path("nclink-sim"), "--broker", broker.url()}, (dir.path / "plain.log").string());
    REQUIRE(eventually([&] { return plain.count("answering as") == 1; }, 20s));
    CHECK(plain.count("metrics on") == 0);
    plain.signal(SIGTERM);
    CHECK(plain.wait_exit(10s) == std::optional<int>(0));

    ChildProcess sim({binary_path("nclink-sim"), "--broker", broker.url(), "--metrics", "127.0.0.1:0"},
                     (dir.path / "sim.log").string());
    REQUIRE(eventually([&] { return logged_port(sim) > 0; }, 20s));
    httplib::Client http("127.0.0.1", logged_port(sim));
    std::vector<PromSample> samples;
    std::string text;
    const std::map<std::string, std::string> dev{{"dev", kSimMillDevice}};
    REQUIRE(eventually(
        [&] {
            auto r = http.Get("/metrics");
            if (!r || r->status != 200) return false;
            text = r->body;
            samples.clear();
            (void)exposition_problems(text, &samples);
            auto sample_dtus = dev;
            sample_dtus["kind"] = "sample";
            return prom_value(samples, "nclink_adapter_dtus_sent_total", sample_dtus).value_or(0) >= 2;
        },
        30s));
    check_exposition(text);
    bool lateness = false;
    for (const auto& s : samples) lateness = lateness || s.name == "nclink_adapter_sampling_lateness_seconds_count";
    CHECK(lateness);
    sim.signal(SIGTERM);
    CHECK(sim.wait_exit(10s) == std::optional<int>(0));
}
