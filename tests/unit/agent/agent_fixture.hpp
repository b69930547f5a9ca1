// An agent on the loopback broker with a manual clock, and peers to talk to
// it: an application side that sees every message ("#"), and raw terminals
// that play adapters (with a last will) or applications.
#pragma once

#include <nclink/agent.hpp>
#include <nclink/dtu.hpp>
#include <nclink/testing/loopback_transport.hpp>
#include <nclink/topics.hpp>

#include "support/wait.hpp"
#include "support/adapter_fixture.hpp"  // AppSide, FakeDriver, scratch_dir

#include <catch2/catch.hpp>

#include <filesystem>
#include <memory>
#include <string>

namespace nclink::test {

inline Message offline_will(const std::string& tid) {
    return Message{topics::notify_state(tid), Json{{"tid", tid}, {"state", "offline"}}.dump(), 1, true};
}

struct AgentFixture {
    explicit AgentFixture(AgentConfig extra = {}, bool start_now = true) : config(std::move(extra)) {
        config.share_group.clear();  // the loopback broker has no shared subscriptions
        app = peer("app");
        app->subscribe("#");
        if (start_now) start_agent();
    }
    ~AgentFixture() {
        if (agent) agent->stop();
        if (!config.state_dir.empty()) {
            std::error_code ec;
            std::filesystem::remove_all(config.state_dir, ec);
        }
    }

    std::unique_ptr<AppSide> peer(const std::string& client_id, std::optional<Message> will = std::nullopt) {
        LoopbackOptions o;
        o.client_id = client_id;
        o.last_will = std::move(will);
        return std::make_unique<AppSide>(make_loopback_transport(broker, o));
    }

    void start_agent() {
        agent = std::make_unique<Agent>(config);
        LoopbackOptions o;
        o.client_id = "agent-" + std::to_string(++agents_started);
        agent->use_transport(make_loopback_transport(broker, o));
        agent->use_clock(clock);
        auto started = agent->start();
        INFO((started.ok() ? std::string() : started.error().describe()));
        REQUIRE(started.ok());
        REQUIRE(eventually([&] { return agent->stats().transport.connects >= 1; }));
    }
    void restart_agent() {
        agent->stop();
        agent.reset();
        start_agent();
    }

    /// An adapter's online state, retained (as our adapter publishes on connect).
    void announce(AppSide& from, const std::string& tid, const std::string& state = "online") {
        from.send(topics::notify_state(tid), Json{{"tid", tid}, {"state", state}}.dump(), true);
    }

    Json register_as(AppSide& from, const std::string& cli, const std::string& id, Json private_info = nullptr) {
        Json request = {{"@id", id}, {"cli_uuid", cli}};
        if (!private_info.is_null()) request["privateInfo"] = private_info;
        return app_wait_after(from, topics::register_request(), topics::register_response(cli), request);
    }

    /// Sends from `from` and waits for the next message on `reply_topic` (seen by app).
    Json app_wait_after(AppSide& from, const std::string& topic, const std::string& reply_topic, const Json& payload) {
        const std::size_t before = app->on(reply_topic).size();
        from.send(topic, payload.dump());
        return app->wait(reply_topic, before + 1);
    }

    void advance(std::chrono::milliseconds by) { clock->advance(by); }

    AgentConfig config;
    LoopbackBroker broker;
    std::shared_ptr<ManualClock> clock = std::make_shared<ManualClock>();
    std::unique_ptr<AppSide> app;
    std::unique_ptr<Agent> agent;
    int agents_started = 0;
};

inline std::optional<TerminalInfo> terminal(Agent& agent, const std::string& id) {
    for (auto& t : agent.terminals())
        if (t.id == id) return t;
    return std::nullopt;
}
/// "" while the agent does not know `id` (safe inside eventually()).
inline std::string status_of(Agent& agent, const std::string& id) {
    auto t = terminal(agent, id);
    return t ? t->status : std::string();
}
inline std::string kind_of(Agent& agent, const std::string& id) {
    auto t = terminal(agent, id);
    return t ? t->kind : std::string();
}

}  // namespace nclink::test
