// `nclink discovery` (8.2.3/8.2.4) against a real mosquitto: with an agent it
// lists the adapter that registered, as lines and as JSON; without one
// nobody answers and the command says so with exit status 1.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>

#include "support/cli.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("nclink discovery lists the adapters the agent knows, and fails without an agent") {
    if (!cli_built()) return;
    MosquittoBroker broker;
    const std::string common = "--broker " + broker.url() + " --timeout 1500 ";

    // No agent: Discovery is an agent feature, nobody answers.
    const CliRun alone = run_cli("discovery " + common);
    CHECK(alone.status == 1);

    AgentConfig agent_config;
    agent_config.broker_url = broker.url();
    agent_config.client_id = "agent-cli";
    Agent agent(agent_config);
    REQUIRE(agent.start().ok());
    AdapterConfig config;
    config.broker_url = broker.url();
    config.model_path = sim_mill_path();
    config.register_timeout = 300ms;
    auto adapter = started_adapter(config, sim_for(config.model_path));
    REQUIRE(eventually([&] { return adapter->stats().registered; }, 20s));

    CliRun listed;
    REQUIRE(eventually(
        [&] {
            listed = run_cli("discovery " + common);
            return listed.status == 0 && listed.out.find(kSimMillDevice) != std::string::npos;
        },
        20s));
    INFO(listed.out);
    CHECK(listed.out.find("online") != std::string::npos);

    const CliRun json = run_cli("discovery --json " + common);
    REQUIRE(json.status == 0);
    const Json list = Json::parse(json.out);
    REQUIRE(list.is_array());
    bool found = false;
    for (const auto& d : list)
        if (d["guid"] == kSimMillDevice) {
            found = true;
            CHECK(d["status"] == "online");
        }
    CHECK(found);

    CHECK(run_cli("discovery --broker " + broker.url() + " extra").status != 0);  // a usage error
    adapter->stop();
    agent.stop();
}
