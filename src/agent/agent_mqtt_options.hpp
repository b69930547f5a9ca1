// The MQTT options of the agent's own broker connection, from its
// configuration: the broker section, and the in-flight window sized for an
// agent that answers for every terminal of the plant.
#pragma once

#include <nclink/agent.hpp>
#include <nclink/mqtt_transport.hpp>

#include <string>

namespace nclink::agent_detail {

/// `client_suffix` makes the default client id "<agent_id>-<suffix>" unique
/// per instance (unused when the configuration names a client id).
MqttOptions agent_mqtt_options(const AgentConfig& config, const std::string& client_suffix);

}  // namespace nclink::agent_detail
