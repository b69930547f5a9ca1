#include "transport/broker_settings.hpp"

#include <nclink/adapter_config.hpp>
#include <nclink/agent.hpp>

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::transport_detail;
using namespace std::chrono_literals;

namespace {
BrokerSettings with_tls() {
    BrokerSettings s;
    s.tls = MqttTlsOptions{"/pki/ca.pem", "/pki/me.pem", "/pki/me.key", "", true};
    return s;
}
}  // namespace

TEST_CASE("broker settings: equal settings compare equal and name no change") {
    const BrokerSettings a = with_tls();
    const BrokerSettings b = with_tls();
    CHECK(a == b);
    CHECK_FALSE(a != b);
    CHECK(broker_changes(a, b).empty());
    CHECK(describe_broker_changes(broker_changes(a, b)).empty());
    CHECK(broker_reload_keys(a, b).empty());
    CHECK(BrokerSettings{} == BrokerSettings{});
}

TEST_CASE("broker settings: every field counts for equality and is named by its configuration key") {
    const BrokerSettings base = with_tls();
    struct Case {
        const char* name;
        void (*change)(BrokerSettings&);
    };
    const Case cases[] = {
        {"url", [](BrokerSettings& s) { s.broker_url = "ssl://plant:8883"; }},
        {"failover", [](BrokerSettings& s) { s.failover_urls = {"ssl://plant-2:8883"}; }},
        {"client_id", [](BrokerSettings& s) { s.client_id = "mill-7"; }},
        {"username", [](BrokerSettings& s) { s.username = "mes"; }},
        {"password", [](BrokerSettings& s) { s.password = "secret"; }},
        {"tls.ca_file", [](BrokerSettings& s) { s.tls->ca_file = "/pki/other-ca.pem"; }},
        {"tls.cert_file", [](BrokerSettings& s) { s.tls->cert_file = "/pki/other.pem"; }},
        {"tls.key_file", [](BrokerSettings& s) { s.tls->key_file = "/pki/other.key"; }},
        {"tls.key_password", [](BrokerSettings& s) { s.tls->key_password = "pass"; }},
        {"tls.verify", [](BrokerSettings& s) { s.tls->verify_server = false; }},
        {"tls", [](BrokerSettings& s) { s.tls.reset(); }},
        {"mqtt_version", [](BrokerSettings& s) { s.mqtt_version = 5; }},
        {"keep_alive_s", [](BrokerSettings& s) { s.keep_alive = 60s; }},
        {"connect_timeout_ms", [](BrokerSettings& s) { s.connect_timeout = 30s; }},
        {"reconnect_min_ms", [](BrokerSettings& s) { s.reconnect_min = 2s; }},
        {"reconnect_max_ms", [](BrokerSettings& s) { s.reconnect_max = 60s; }},
        {"clean_session", [](BrokerSettings& s) { s.clean_session = false; }},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        BrokerSettings changed = base;
        c.change(changed);
        CHECK(changed != base);
        CHECK(broker_changes(base, changed) == std::vector<std::string>{c.name});
        CHECK(broker_changes(changed, base) == std::vector<std::string>{c.name});
    }
}

TEST_CASE("broker settings: the diff names every change in file order, on one line for a person") {
    const BrokerSettings was = with_tls();
    BrokerSettings now = was;
    now.keep_alive = 5s;
    now.tls->ca_file = "/pki/new-ca.pem";
    now.broker_url = "ssl://plant:8883";
    now.tls->verify_server = false;
    const auto changes = broker_changes(was, now);
    CHECK(changes == std::vector<std::string>{"url", "tls.ca_file", "tls.verify", "keep_alive_s"});
    CHECK(describe_broker_changes(changes) == "url, tls.ca_file, tls.verify, keep_alive_s");
}

TEST_CASE("broker settings: a reload reports broker keys with every TLS change folded into broker.tls") {
    const BrokerSettings was = with_tls();
    BrokerSettings now = was;
    now.tls->ca_file = "/pki/new-ca.pem";
    now.tls->key_file = "/pki/new.key";
    now.username = "mes";
    CHECK(broker_reload_keys(was, now) == std::vector<std::string>{"broker.username", "broker.tls"});
    BrokerSettings plain = was;
    plain.tls.reset();
    CHECK(broker_reload_keys(was, plain) == std::vector<std::string>{"broker.tls"});
    // The failover list is ordered: the same brokers in another order are another list.
    BrokerSettings listed = was;
    listed.failover_urls = {"b:1883", "c:1883"};
    CHECK(broker_reload_keys(was, listed) == std::vector<std::string>{"broker.failover"});
    BrokerSettings reordered = listed;
    reordered.failover_urls = {"c:1883", "b:1883"};
    CHECK(broker_reload_keys(listed, reordered) == std::vector<std::string>{"broker.failover"});
}

TEST_CASE("broker settings: read from a configuration and applied to the transport options") {
    AdapterConfig adapter;
    adapter.broker_url = "ssl://plant:8883";
    adapter.client_id = "mill-1";
    adapter.username = "mill";
    adapter.password = "pw";
    adapter.tls = MqttTlsOptions{"/ca.pem", "", "", "", false};
    adapter.mqtt_version = 5;
    adapter.keep_alive = 7s;
    adapter.clean_session = false;
    adapter.failover_urls = {"plant-2:8883", "ssl://plant-3:8883"};
    const BrokerSettings s = BrokerSettings::of(adapter);
    CHECK(s.broker_url == "ssl://plant:8883");
    CHECK(s.failover_urls == std::vector<std::string>{"plant-2:8883", "ssl://plant-3:8883"});
    CHECK(s.client_id == "mill-1");
    CHECK(s.clean_session == false);

    MqttOptions options;
    options.ack_timeout = 1234ms;
    s.apply_to(options);
    CHECK(BrokerSettings::of(options) == s);
    CHECK(options.failover_urls == s.failover_urls);
    CHECK(options.ack_timeout == 1234ms);  // not a broker setting: left alone

    // The connection's timers reach the transport (a slow cluster, docs/scaling.md).
    adapter.connect_timeout = 30s;
    adapter.reconnect_min = 2s;
    adapter.reconnect_max = 40s;
    MqttOptions slow;
    BrokerSettings::of(adapter).apply_to(slow);
    CHECK(slow.connect_timeout == 30s);
    CHECK(slow.reconnect_min == 2s);
    CHECK(slow.reconnect_max == 40s);

    // A configuration without clean_session (the agent's) keeps the default.
    AgentConfig agent;
    agent.broker_url = adapter.broker_url;
    CHECK(BrokerSettings::of(agent).clean_session == true);
    CHECK(BrokerSettings::of(agent).broker_url == "ssl://plant:8883");

    // Back into a configuration: the broker fields, nothing else.
    AgentConfig into;
    into.agent_id = "agent-7";
    s.apply_to(into);
    CHECK(BrokerSettings::of(into) == [&] {
        BrokerSettings expected = s;
        expected.clean_session = true;  // the agent has none
        return expected;
    }());
    CHECK(into.agent_id == "agent-7");
    AdapterConfig adapter_into;
    s.apply_to(adapter_into);
    CHECK(BrokerSettings::of(adapter_into) == s);
}
