// The broker section every configuration file has (adapter, agent, bridge,
// gateway): url, client id, credentials, MQTT version, keep-alive and TLS.
#pragma once

#include "core/config_common.hpp"

#include <nclink/mqtt_transport.hpp>

#include <optional>
#include <string>

namespace nclink::detail {

/// Makes the TLS files of a broker section absolute against the directory of
/// `config_path` when relative.
void resolve_tls_paths(const std::string& config_path, std::optional<MqttTlsOptions>& tls);

/// "tls" of a broker section.
Result<void> read_tls(ConfigReader& broker, std::optional<MqttTlsOptions>& tls);

/// The keys every broker section has (url, client_id, username, password,
/// mqtt_version, keep_alive_s, tls); the caller reads its own extra keys,
/// then calls broker.no_unknown_keys().
template <class Config>
Result<void> read_broker_common(ConfigReader& broker, Config& c) {
    NCLINK_TRY(broker.str("url", c.broker_url));
    NCLINK_TRY(broker.str("client_id", c.client_id));
    NCLINK_TRY(broker.str("username", c.username));
    NCLINK_TRY(broker.str("password", c.password));
    NCLINK_TRY(broker.count("mqtt_version", c.mqtt_version));
    NCLINK_TRY(broker.duration("keep_alive_s", c.keep_alive));
    NCLINK_TRY(read_tls(broker, c.tls));
    if (c.mqtt_version != 4 && c.mqtt_version != 5)
        return broker.fail(ErrorCode::value_type, "mqtt_version", "must be 4 (MQTT 3.1.1) or 5");
    return ok_result();
}

}  // namespace nclink::detail
