// nclink on a 3-node cluster, RabbitMQ or ejabberd: an adapter (libmosquitto
// transport, mqtt_version "auto") connected to node 1 and an application's
// Client (paho) connected to node 2, logged in where the broker wants it; a
// Query (8.2.19/8.2.20) goes from one node to the other and back. Where the
// brokers differ the test says so (`rabbitmq` below): RabbitMQ 3.10 closes an
// MQTT 5 CONNECT, so "auto" falls back to 3.1.1 and the Client is on 3.1.1;
// ejabberd takes MQTT 5 ("auto" gets in at once, the Client is on 5) and
// refuses a CONNECT without a login.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>

#include "cluster_configs.hpp"
#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // scratch_dir(), FakeDriver
#include "support/patient_query.hpp"

#include <cstdio>
#include <type_traits>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

template <class Cluster>
void query_across_nodes(Cluster& cluster, const Login& login, const char* broker) {
    constexpr bool rabbitmq = std::is_same_v<Cluster, RabbitCluster>;

    AdapterConfig config = adapter_config(cluster, 0, "cluster-adapter", login);
    auto driver = std::make_shared<FakeDriver>();
    Adapter adapter(config, driver, probe_logger());
    REQUIRE(adapter.start());
    REQUIRE(eventually([&] { return adapter.state() == AdapterState::normal; }, 60s));
    if constexpr (rabbitmq) {
        // The MQTT 5 attempt that came first failed; 3.1.1 connected.
        CHECK(adapter.stats().transport.connect_failures >= 1);
    } else {
        // "auto" got in with MQTT 5 at the first attempt.
        CHECK(adapter.stats().transport.connect_failures == 0);
    }
    CHECK(adapter.stats().transport.connects == 1);

    // An adapter the broker never lets in: on RabbitMQ one asking for MQTT 5
    // without "auto", on ejabberd one without a login (CONNACK "not
    // authorized").
    {
        AdapterConfig spoilt = config;
        spoilt.client_id = "cluster-adapter-refused";
        spoilt.device_id.clear();
        if constexpr (rabbitmq) {
            spoilt.mqtt_version = 5;
        } else {
            spoilt.username.clear();
            spoilt.password.clear();
        }
        spoilt.persistence_dir = scratch_dir(spoilt.client_id);
        Adapter refused(spoilt, std::make_shared<FakeDriver>(), probe_logger());
        REQUIRE(refused.start());
        CHECK(eventually([&] { return refused.stats().transport.connect_failures >= 3; }, 30s));
        CHECK(refused.stats().transport.connects == 0);
        refused.stop();
        std::error_code ignored;
        std::filesystem::remove_all(spoilt.persistence_dir, ignored);
    }

    ClientOptions o;
    o.ex_cid = "cluster-app";
    o.default_timeout = 300ms;  // the registration nobody answers (no agent here)
    auto made = Client::create(client_mqtt(cluster, 1, login, rabbitmq ? 4 : 5), o);
    REQUIRE(made);
    auto& client = **made;
    auto outcome = client.connect(30s);
    REQUIRE(outcome);
    CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);

    // The adapter's SUBSCRIBE may still be on its way through the cluster:
    // asked again until answered.
    const auto asked = std::chrono::steady_clock::now();
    const auto answer = patient_query(client);
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - asked);
    REQUIRE(answer.size() == 2);
    REQUIRE(answer[0].values);
    CHECK(*answer[0].values == Json::array({12.5}));
    REQUIRE(answer[1].values);
    CHECK(*answer[1].values == Json::array({"running"}));
    std::printf("%s: a Query from node 2 answered by the adapter on node 1 in %lld ms\n", broker,
                static_cast<long long>(took.count()));

    client.stop();
    adapter.stop();
    std::error_code ignored;
    std::filesystem::remove_all(config.persistence_dir, ignored);
}

}  // namespace

TEST_CASE("RabbitMQ cluster: an adapter on node 1 answers a Query from a client on node 2, MQTT auto falling back to 3.1.1") {
    NCLINK_NEEDS_RABBITMQ();
    RabbitCluster rabbit;
    query_across_nodes(rabbit, Login{}, "RabbitMQ");
}

TEST_CASE("ejabberd cluster: an adapter on node 1 answers a Query from a client on node 2, logged in, on MQTT 5") {
    NCLINK_NEEDS_EJABBERD();
    EjabberdCluster ejabberd;
    query_across_nodes(ejabberd, ejabberd_login(), "ejabberd");
}
