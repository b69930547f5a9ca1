#include "transport/broker_config.hpp"

namespace nclink::detail {

void resolve_tls_paths(const std::string& config_path, std::optional<MqttTlsOptions>& tls) {
    if (!tls) return;
    resolve_against(config_path, tls->ca_file);
    resolve_against(config_path, tls->cert_file);
    resolve_against(config_path, tls->key_file);
}

Result<void> read_tls(ConfigReader& broker, std::optional<MqttTlsOptions>& tls) {
    const Json* section = broker.object("tls");
    if (!section) return ok_result();
    if (!section->is_object()) return broker.fail(ErrorCode::value_type, "tls", "must be an object");
    ConfigReader t(*section, broker.where() + "tls.", pointer_append(broker.pointer(), "tls"));
    MqttTlsOptions o = tls.value_or(MqttTlsOptions{});
    NCLINK_TRY(t.str("ca_file", o.ca_file));
    NCLINK_TRY(t.str("cert_file", o.cert_file));
    NCLINK_TRY(t.str("key_file", o.key_file));
    NCLINK_TRY(t.str("key_password", o.key_password));
    NCLINK_TRY(t.boolean("verify", o.verify_server));
    NCLINK_TRY(t.no_unknown_keys());
    tls = o;
    return ok_result();
}

Result<void> read_broker_settings(ConfigReader& broker, transport_detail::BrokerSettings& s) {
    NCLINK_TRY(broker.str("url", s.broker_url));
    NCLINK_TRY(broker.str("client_id", s.client_id));
    NCLINK_TRY(broker.str("username", s.username));
    NCLINK_TRY(broker.str("password", s.password));
    NCLINK_TRY(broker.count("mqtt_version", s.mqtt_version));
    NCLINK_TRY(broker.duration("keep_alive_s", s.keep_alive));
    NCLINK_TRY(read_tls(broker, s.tls));
    if (s.mqtt_version != 4 && s.mqtt_version != 5)
        return broker.fail(ErrorCode::value_type, "mqtt_version", "must be 4 (MQTT 3.1.1) or 5");
    return ok_result();
}

}  // namespace nclink::detail
