// An agent answering through $share on an ejabberd cluster (Debian's 23.01,
// mod_mqtt): what happens when a broker without shared subscriptions is
// given one. mod_mqtt closes the connection at a SUBSCRIBE to $share/....
// An agent that makes its own transport checks for that at start and
// answers through plain subscriptions (test_agent_on_cluster.cpp); this
// test hands the agent a transport of its own making, which skips the
// check, to hold the transport's side: a broker's DISCONNECT is a lost
// connection, connected again. Every program logs in (the broker section's
// "username"/"password"; mod_mqtt refuses a CONNECT without a password).
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>
#include <nclink/paho_transport.hpp>

#include "cluster_configs.hpp"
#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver

#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

const Login login = ejabberd_login();

}  // namespace

// The agent's default, shared subscriptions, on ejabberd: mod_mqtt answers
// the SUBSCRIBE to $share/... by ending the connection (MQTT 5: DISCONNECT
// 0x9E first). Nobody is registered either way; what the agent's transport
// (paho) sees differs. At 3.1.1 the socket closes: connection lost, and it
// connects and subscribes again, over and over. At MQTT 5 paho takes the
// broker's DISCONNECT for the end of the connection without calling the
// connection-lost callback, the only one the transport listens to: the link
// stays "connected", deaf, with no reconnection.
TEST_CASE(
    "ejabberd cluster: an agent on a transport of its own subscribing $share is dropped at its SUBSCRIBE and registers nobody") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;

    AdapterConfig config = adapter_config(ejabberd, 0, "ej-shared-adapter", login);
    Adapter adapter(config, std::make_shared<FakeDriver>(), probe_logger());
    REQUIRE(adapter.start());

    std::uint64_t connects[2] = {0, 0};
    std::uint64_t failures[2] = {0, 0};
    for (int level : {5, 4}) {
        INFO("agent on MQTT " << level);
        AgentConfig agent_settings = agent_config(ejabberd, 2, "ej-shared-agent-" + std::to_string(level), login, level);
        REQUIRE(agent_settings.share_group == "nclink-agent");
        Agent agent(agent_settings, probe_logger());
        MqttOptions mqtt = client_mqtt(ejabberd, 2, login, level);
        mqtt.client_id = agent_settings.client_id;
        auto transport = make_paho_transport(mqtt, probe_logger());
        REQUIRE(transport);
        agent.use_transport(std::move(transport).value());
        REQUIRE(agent.start());
        CHECK(agent.share_group_in_use() == "nclink-agent");
        REQUIRE(eventually([&] { return agent.stats().transport.connects >= 1; }, 30s));
        // Until it has connected again: at 3.1.1 ejabberd closes the
        // connection, at MQTT 5 it sends DISCONNECT 0x9E first, which the
        // paho transport takes for a lost connection too (before, it stayed
        // on its first connection, deaf). At once on an idle box; a loaded
        // one may delay the reconnection's back-off.
        eventually([&] { return agent.stats().transport.connects > 1; }, 30s);
        CHECK_FALSE(adapter.stats().registered);
        CHECK(agent.stats().registrations == 0);
        const std::size_t k = level == 5 ? 0 : 1;
        connects[k] = agent.stats().transport.connects;
        failures[k] = agent.stats().transport.connect_failures;
        agent.stop();
    }
    INFO("MQTT 5: " << connects[0] << " connects, " << failures[0] << " failures; 3.1.1: " << connects[1] << " connects, "
                    << failures[1] << " failures");
    CHECK(connects[0] > 1);
    CHECK(connects[1] > 1);
    std::printf(
        "ejabberd: an agent with share_group \"nclink-agent\" registered nobody; dropped at its SUBSCRIBE, it connected %llu "
        "time(s) on MQTT 5 (%llu failed attempts) and %llu times on MQTT 3.1.1 (%llu failed attempts)\n",
        static_cast<unsigned long long>(connects[0]), static_cast<unsigned long long>(failures[0]),
        static_cast<unsigned long long>(connects[1]), static_cast<unsigned long long>(failures[1]));

    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}
