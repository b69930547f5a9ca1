// nclink on an ejabberd cluster (Debian's 23.01, mod_mqtt), with the
// settings docs/scaling.md gives for it: every program logs in (the broker
// section's "username"/"password"; mod_mqtt refuses a CONNECT without a
// password), MQTT 5 or "auto" (ejabberd takes 5), and an agent with plain
// subscriptions (share_group ""): mod_mqtt closes the connection at a
// SUBSCRIBE to $share/..., which the last test here shows. The agents with
// plain subscriptions run on both clusters in test_agent_on_cluster.cpp.
#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_configs.hpp"
#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir(), FakeDriver
#include "support/patient_query.hpp"

#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

const Login login = ejabberd_login();

}  // namespace

TEST_CASE("ejabberd cluster: an adapter on node 1 answers a Query from a client on node 2, logged in, on MQTT 5") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;

    AdapterConfig config = adapter_config(ejabberd, 0, "ej-adapter", login);
    auto driver = std::make_shared<FakeDriver>();
    Adapter adapter(config, driver, probe_logger());
    REQUIRE(adapter.start());
    REQUIRE(eventually([&] { return adapter.state() == AdapterState::normal; }, 60s));
    // "auto" got in with MQTT 5 at the first attempt.
    CHECK(adapter.stats().transport.connect_failures == 0);
    CHECK(adapter.stats().transport.connects == 1);

    // Without a login an adapter never gets in (CONNACK "not authorized").
    {
        AdapterConfig anonymous = config;
        anonymous.client_id = "ej-adapter-anonymous";
        anonymous.device_id.clear();
        anonymous.username.clear();
        anonymous.password.clear();
        anonymous.persistence_dir = scratch_dir("ej-adapter-anonymous");
        Adapter refused(anonymous, std::make_shared<FakeDriver>(), probe_logger());
        REQUIRE(refused.start());
        CHECK(eventually([&] { return refused.stats().transport.connect_failures >= 3; }, 30s));
        CHECK(refused.stats().transport.connects == 0);
        refused.stop();
        std::error_code ignored;
        std::filesystem::remove_all(anonymous.persistence_dir, ignored);
    }

    ClientOptions o;
    o.ex_cid = "ej-app";
    o.default_timeout = 300ms;  // the registration nobody answers (no agent here)
    auto made = Client::create(client_mqtt(ejabberd, 1, login, 5), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);

    // The adapter's SUBSCRIBE is done by the time it is normal; asked again
    // all the same until answered, as on RabbitMQ.
    const auto asked = std::chrono::steady_clock::now();
    const auto answer = patient_query(client);
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - asked);
    REQUIRE(answer.size() == 2);
    REQUIRE(answer[0].values);
    CHECK(*answer[0].values == Json::array({12.5}));
    REQUIRE(answer[1].values);
    CHECK(*answer[1].values == Json::array({"running"}));
    std::printf("ejabberd: a Query from node 2 answered by the adapter on node 1 in %lld ms\n",
                static_cast<long long>(took.count()));

    client.stop();
    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}

// The agent's default, shared subscriptions, on ejabberd: mod_mqtt answers
// the SUBSCRIBE to $share/... by ending the connection (MQTT 5: DISCONNECT
// 0x9E first). Nobody is registered either way; what the agent's transport
// (paho) sees differs. At 3.1.1 the socket closes: connection lost, and it
// connects and subscribes again, over and over. At MQTT 5 paho takes the
// broker's DISCONNECT for the end of the connection without calling the
// connection-lost callback, the only one the transport listens to: the link
// stays "connected", deaf, with no reconnection.
TEST_CASE("ejabberd cluster: an agent with the default share_group is dropped at its SUBSCRIBE and registers nobody") {
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
        REQUIRE(agent.start());
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
