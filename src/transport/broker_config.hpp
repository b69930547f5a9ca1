// The broker section every configuration file has (adapter, agent, bridge,
// gateway): url, client id, credentials, MQTT version, keep-alive, TLS and
// the brokers to fail over to.
#pragma once

#include "core/config_common.hpp"
#include "transport/broker_settings.hpp"

#include <nclink/mqtt_transport.hpp>

#include <optional>
#include <string>

namespace nclink::transport_detail {

/// Makes the TLS files of a broker section absolute against the directory of
/// `config_path` when relative.
void resolve_tls_paths(const std::string& config_path, std::optional<MqttTlsOptions>& tls);

/// "tls" of a broker section.
Result<void> read_tls(core_detail::ConfigReader& broker, std::optional<MqttTlsOptions>& tls);

/// The keys every broker section has (url, client_id, username, password,
/// mqtt_version, keep_alive_s, connect_timeout_ms, reconnect_min_ms,
/// reconnect_max_ms, tls, failover) into `settings`; the caller reads its own
/// extra keys, then calls broker.no_unknown_keys().
Result<void> read_broker_settings(core_detail::ConfigReader& broker, transport_detail::BrokerSettings& settings);

/// The same into a configuration (AdapterConfig, AgentConfig, BridgeConfig),
/// through BrokerSettings.
template <class Config>
Result<void> read_broker_common(core_detail::ConfigReader& broker, Config& c) {
    auto settings = transport_detail::BrokerSettings::of(c);
    NCLINK_TRY(read_broker_settings(broker, settings));
    settings.apply_to(c);
    return ok_result();
}

}  // namespace nclink::transport_detail
