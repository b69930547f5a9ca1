// What the agent subscribes to, and at which QoS: Sample DTUs, which only
// tell it that their terminal lives (3.22), at QoS 0, so a broker neither
// counts them against the agent's in-flight window nor queues the agent's
// requests behind them; everything it must answer or keep at QoS 1.
#include <nclink/agent.hpp>
#include <nclink/topics.hpp>

#include "support/recording_transport.hpp"

#include <catch2/catch.hpp>

#include <memory>
#include <string>
#include <utility>
#include <vector>

using namespace nclink;

namespace {

std::vector<std::pair<std::string, int>> subscriptions_of(AgentConfig config) {
    config.share_group.clear();
    Agent agent(config);
    auto transport = std::make_unique<test::RecordingTransport>();
    test::RecordingTransport* seen = transport.get();
    agent.use_transport(std::move(transport));
    REQUIRE(agent.start().ok());
    auto out = seen->subscriptions();
    agent.stop();
    return out;
}

int qos_of(const std::vector<std::pair<std::string, int>>& subscriptions, const std::string& filter) {
    for (const auto& [f, qos] : subscriptions)
        if (f == filter) return qos;
    return -1;
}

}  // namespace

TEST_CASE("the agent takes Sample DTUs at QoS 0 and what it answers or keeps at QoS 1") {
    const auto subscribed = subscriptions_of(AgentConfig{});
    CHECK(qos_of(subscribed, "Sample/#") == 0);
    CHECK(qos_of(subscribed, topics::register_request()) == 1);
    CHECK(qos_of(subscribed, topics::discovery_request("+")) == 1);
    CHECK(qos_of(subscribed, topics::notify_state("+")) == 1);
    CHECK(qos_of(subscribed, topics::event("+")) == 1);
    for (const auto& [filter, qos] : subscribed)
        if (filter != "Sample/#") CHECK(qos == 1);
}

TEST_CASE("without observe_samples the agent does not subscribe to Sample DTUs") {
    AgentConfig config;
    config.observe_samples = false;
    const auto subscribed = subscriptions_of(config);
    CHECK(qos_of(subscribed, "Sample/#") == -1);
    CHECK(qos_of(subscribed, topics::register_request()) == 1);
}
