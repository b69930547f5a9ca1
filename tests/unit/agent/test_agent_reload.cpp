// Agent::reload: what nclink-agent does on SIGHUP. Rules that are safe to
// change while running take effect for the next DTU; the rest waits for a
// restart and is reported; a refused configuration changes nothing.
#include "unit/agent/agent_fixture.hpp"

#include <algorithm>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

bool has(const std::vector<std::string>& keys, const std::string& key) {
    return std::find(keys.begin(), keys.end(), key) != keys.end();
}

Json set_from(AgentFixture& f, const std::string& app, const std::string& id) {
    return f.app_wait_after(*f.app, topics::set_request("mill-1", app), topics::set_response("mill-1", app),
                            Json{{"@id", id}, {"guid", "mill-1"}, {"values", Json::array()}});
}

}  // namespace

TEST_CASE("reload: new access rules answer the next request and are reported applied") {
    AgentFixture f;
    auto side = f.peer("mill-1", offline_will("mill-1"));
    f.announce(*side, "mill-1");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online"; }));
    // Allowed before: left to the adapter (no agent answer).
    f.app->send(topics::set_request("mill-1", "viewer"), Json{{"@id", "s0"}, {"guid", "mill-1"}, {"values", Json::array()}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().pending == 1; }));

    AgentConfig next = f.config;
    next.access.applications["viewer"]["*"] = access_read;
    auto report = f.agent->reload(next);
    REQUIRE(report.ok());
    CHECK(report->applied == std::vector<std::string>{"access"});
    CHECK(report->restart_needed.empty());
    const Json denied = set_from(f, "viewer", "s1");
    CHECK(denied["error"] == 301);
    CHECK(f.agent->stats().denied == 1);
}

TEST_CASE("reload: a closed allowlist refuses new registrations and keeps accepted ones") {
    AgentFixture f;
    REQUIRE(f.register_as(*f.app, "mes-1", "r1")["code"] == "OK");
    AgentConfig next = f.config;
    next.registration.open = false;
    next.registration.terminals["mes-2"] = TerminalEntry{"application", ""};
    auto report = f.agent->reload(next);
    REQUIRE(report.ok());
    CHECK(has(report->applied, "registration"));
    CHECK(f.register_as(*f.app, "stranger", "r2")["error"] == 301);
    CHECK(f.register_as(*f.app, "mes-2", "r3")["code"] == "OK");
    CHECK(kind_of(*f.agent, "mes-2") == "application");
    CHECK(terminal(*f.agent, "mes-1")->registered);
}

TEST_CASE("reload: request_timeout_ms applies to requests that arrive afterwards") {
    AgentConfig c;
    c.request_timeout = 5000ms;
    AgentFixture f(c);
    auto side = f.peer("mill-1", offline_will("mill-1"));
    f.announce(*side, "mill-1");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mill-1") == "online"; }));
    AgentConfig next = f.config;
    next.request_timeout = 100ms;
    REQUIRE(f.agent->reload(next).ok());
    f.app->send(topics::query_request("mill-1", "mes"), Json{{"@id", "q1"}, {"guid", "mill-1"}, {"ids", {"pos"}}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().pending == 1; }));
    f.advance(100ms);
    const Json answer = f.app->wait(topics::query_response("mill-1", "mes"));
    CHECK(answer["error"] == 203);
}

TEST_CASE("reload: broker identity and state keys wait for a restart and are listed") {
    AgentFixture f;
    AgentConfig next = f.config;
    next.broker_url = "tcp://elsewhere:1883";
    next.agent_id = "agent-b";
    next.state_dir = "/nonexistent/state";
    next.tick = 5ms;
    next.max_in_flight = 10;
    next.discovery_link = false;
    next.log_level = LogLevel::debug;
    auto report = f.agent->reload(next);
    REQUIRE(report.ok());
    CHECK(report->restart_needed ==
          std::vector<std::string>{"broker.url", "agent_id", "state_dir", "max_in_flight", "discovery_link", "tick_ms"});
    CHECK(report->applied == std::vector<std::string>{"log_level"});
    // The running agent still answers as itself.
    f.app->send(topics::probe_version("mill-9"), Json{{"@id", "v"}, {"guid", "mill-9"}, {"version", "2"}}.dump());
    REQUIRE(eventually([&] { return !f.app->on(topics::probe_query_request("mill-9", "nclink-agent")).empty(); }));
    // Reloading the same file again reports the pending keys again, nothing new applied.
    auto again = f.agent->reload(next);
    REQUIRE(again.ok());
    CHECK(again->applied.empty());
    CHECK(again->restart_needed.size() == 6);
}

TEST_CASE("reload: an id_pattern that is no regex is refused and nothing changes") {
    AgentFixture f;
    AgentConfig next = f.config;
    next.access.default_rights = access_none;
    next.registration.id_pattern = "([";
    auto report = f.agent->reload(next);
    REQUIRE_FALSE(report.ok());
    CHECK(report.error().code == ErrorCode::value_type);
    CHECK(f.register_as(*f.app, "mes-1", "r1")["code"] == "OK");  // the old rules: open, any id
}

TEST_CASE("reload: log_level changes the level of the logger the agent was given and its copies") {
    std::vector<std::string> lines;
    std::mutex mutex;
    const Logger logger(
        [&](LogLevel, std::string_view m) {
            std::lock_guard<std::mutex> lock(mutex);
            lines.emplace_back(m);
        },
        LogLevel::warn);
    const Logger copy = logger;
    AgentConfig c;
    c.log_level = LogLevel::warn;
    Agent agent(c, logger);
    AgentConfig next = c;
    next.log_level = LogLevel::debug;
    auto report = agent.reload(next);  // before start(): applied as well
    REQUIRE(report.ok());
    CHECK(report->applied == std::vector<std::string>{"log_level"});
    CHECK(copy.min_level() == LogLevel::debug);
    copy.debug("now visible");
    std::lock_guard<std::mutex> lock(mutex);
    CHECK(std::find(lines.begin(), lines.end(), "now visible") != lines.end());
}
