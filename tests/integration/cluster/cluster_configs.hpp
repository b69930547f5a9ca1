// The settings the cluster tests give nclink's programs, filled one way for
// either cluster (RabbitCluster, EjabberdCluster: url(i) of node i, 0-based)
// and either login (Login{} on RabbitMQ, ejabberd_login() on ejabberd), so a
// test body written once over the cluster type sets its programs up the same
// on both. What differs between the brokers (the MQTT version, the share
// group) the test passes in or sets after.
#pragma once

#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/client.hpp>

#include "cluster_probe.hpp"
#include "support/adapter_fixture.hpp"  // test_model_path(), scratch_dir()

#include <chrono>
#include <string>
#include <vector>

namespace nclink::test {

/// The cluster's other nodes, from the one after `node` round: the failover
/// list of a program on `node` (docs/configuration.md, "Failover to other
/// brokers").
template <class Cluster>
std::vector<std::string> other_nodes(const Cluster& cluster, int node) {
    std::vector<std::string> urls;
    for (int k = 1; k < cluster.size(); ++k) urls.push_back(cluster.url((node + k) % cluster.size()));
    return urls;
}

/// An agent on `node`, logged in. The share group stays the default: a test
/// on a cluster sets it to "" (RabbitMQ takes $share/... for a topic name,
/// ejabberd closes the connection at a SUBSCRIBE to it) unless it measures
/// what the default does there.
template <class Cluster>
AgentConfig agent_config(const Cluster& cluster, int node, const std::string& id, const Login& login, int mqtt_version) {
    AgentConfig config;
    config.broker_url = cluster.url(node);
    config.client_id = id;
    config.username = login.username;
    config.password = login.password;
    config.mqtt_version = mqtt_version;
    return config;
}

/// The test adapter (FakeDriver's model) on `node`, logged in, with
/// mqtt_version "auto" (RabbitMQ 3.10 closes the MQTT 5 CONNECT and 3.1.1
/// follows; ejabberd takes 5) and its own scratch directory named `id`.
/// The short register_timeout asks again soon: an agent's SUBSCRIBE may still
/// be on its way through the cluster.
template <class Cluster>
AdapterConfig adapter_config(const Cluster& cluster, int node, const std::string& id, const Login& login) {
    AdapterConfig config;
    config.model_path = test_model_path();
    config.persistence_dir = scratch_dir(id);
    config.broker_url = cluster.url(node);
    config.client_id = id;
    config.username = login.username;
    config.password = login.password;
    config.mqtt_version = 0;  // "auto"
    config.register_timeout = std::chrono::milliseconds(300);
    return config;
}

/// An application Client's MQTT settings on `node`, logged in.
template <class Cluster>
MqttOptions client_mqtt(const Cluster& cluster, int node, const Login& login, int mqtt_version) {
    MqttOptions mqtt;
    mqtt.broker_url = cluster.url(node);
    mqtt.username = login.username;
    mqtt.password = login.password;
    mqtt.mqtt_version = mqtt_version;
    return mqtt;
}

}  // namespace nclink::test
