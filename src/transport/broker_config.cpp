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

}  // namespace nclink::detail
