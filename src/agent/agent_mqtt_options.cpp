#include "agent/agent_mqtt_options.hpp"

#include "transport/broker_settings.hpp"

namespace nclink::agent_detail {

MqttOptions agent_mqtt_options(const AgentConfig& config, const std::string& client_suffix) {
    MqttOptions o;
    transport_detail::BrokerSettings::of(config).apply_to(o);
    if (o.client_id.empty()) o.client_id = config.agent_id + "-" + client_suffix;
    // The agent's answers (registrations, Discovery, the requests it asks in
    // an adapter's place) share one window. At 10,000 terminals starting
    // together, 64 unacknowledged messages to a busy broker let out about 300
    // answers a second, and an application's Discovery waited behind
    // thousands of them (docs/performance.md).
    o.outbox.max_in_flight = config.max_in_flight;
    return o;
}

}  // namespace nclink::agent_detail
