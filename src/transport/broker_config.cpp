#include "transport/broker_config.hpp"

namespace nclink::transport_detail {

void resolve_tls_paths(const std::string& config_path, std::optional<MqttTlsOptions>& tls) {
    if (!tls) return;
    core_detail::resolve_against(config_path, tls->ca_file);
    core_detail::resolve_against(config_path, tls->cert_file);
    core_detail::resolve_against(config_path, tls->key_file);
}

Result<void> read_tls(core_detail::ConfigReader& broker, std::optional<MqttTlsOptions>& tls) {
    const Json* section = broker.object("tls");
    if (!section) return ok_result();
    if (!section->is_object()) return broker.fail(ErrorCode::value_type, "tls", "must be an object");
    core_detail::ConfigReader t(*section, broker.where() + "tls.", core_detail::pointer_append(broker.pointer(), "tls"));
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

Result<void> read_broker_settings(core_detail::ConfigReader& broker, transport_detail::BrokerSettings& s) {
    NCLINK_TRY(broker.str("url", s.broker_url));
    NCLINK_TRY(broker.str("client_id", s.client_id));
    NCLINK_TRY(broker.str("username", s.username));
    NCLINK_TRY(broker.str("password", s.password));
    // "auto" (0 in MqttOptions): MQTT 5, or 3.1.1 where the broker refuses 5
    // (a RabbitMQ 3.10 cluster, docs/scaling.md).
    const Json* version = broker.object("mqtt_version");
    if (version && version->is_string() && *version == "auto") {
        s.mqtt_version = 0;
    } else if (version) {
        int given = 0;
        NCLINK_TRY(broker.count("mqtt_version", given));
        if (given != 4 && given != 5)
            return broker.fail(ErrorCode::value_type, "mqtt_version", "must be 4 (MQTT 3.1.1), 5 or \"auto\"");
        s.mqtt_version = given;
    }
    NCLINK_TRY(broker.duration("keep_alive_s", s.keep_alive));
    NCLINK_TRY(read_tls(broker, s.tls));
    return ok_result();
}

}  // namespace nclink::transport_detail
