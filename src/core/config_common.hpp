// The parts the adapter's and the agent's configuration files share: reading
// the file, the broker section, the log level, and paths relative to the file.
#pragma once

#include "core/config_reader.hpp"

#include <nclink/adapter_config.hpp>  // log_level_from_string
#include <nclink/mqtt_transport.hpp>

#include <optional>
#include <string>

namespace nclink::detail {

/// Reads and parses a configuration file (unavailable / syntax_error with the path).
Result<Json> read_config_file(const std::string& path);

/// Makes `p` absolute against the directory of `config_path` when relative.
void resolve_against(const std::string& config_path, std::string& p);
/// The same for the TLS files of a broker section.
void resolve_tls_paths(const std::string& config_path, std::optional<MqttTlsOptions>& tls);

/// "log_level": trace/debug/info/warn/error/off.
Result<void> read_log_level(ConfigReader& top, LogLevel& out);

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
        return make_error(ErrorCode::value_type, "configuration: broker.mqtt_version must be 4 (MQTT 3.1.1) or 5");
    return ok_result();
}

}  // namespace nclink::detail
