#include "transport/broker_config.hpp"

#include "transport/broker_list.hpp"

#include <fmt/format.h>

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

namespace {

// "failover": an array of broker URLs or "host:port" (MqttOptions::
// failover_urls). A bad entry is named by its index and points at itself.
Result<void> read_failover(core_detail::ConfigReader& broker, transport_detail::BrokerSettings& s) {
    const Json* list = broker.object("failover");
    if (!list) return ok_result();
    const auto must = [&] { return broker.fail(ErrorCode::value_type, "failover", "must be an array of broker URLs"); };
    if (!list->is_array()) return must();
    std::vector<std::string> urls;
    for (const Json& entry : *list) {
        if (!entry.is_string()) return must();
        urls.push_back(entry.get<std::string>());
    }
    for (std::size_t i = 0; i < urls.size(); ++i) {
        if (auto problem = failover_entry_problem(s.broker_url, urls, i)) {
            Error e =
                make_error(ErrorCode::value_type, fmt::format("configuration: {}failover[{}]: {}", broker.where(), i, *problem));
            e.pointer = core_detail::pointer_append(core_detail::pointer_append(broker.pointer(), "failover"), std::to_string(i));
            return e;
        }
    }
    s.failover_urls = std::move(urls);
    return ok_result();
}

}  // namespace

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
    // A clustered broker under a connection storm answers CONNECT late (a
    // RabbitMQ cluster took more than 5 s for 1,000 terminals,
    // docs/scaling.md): a plant lengthens these rather than have every
    // terminal give up, fail over and load the next node.
    NCLINK_TRY(broker.duration("connect_timeout_ms", s.connect_timeout));
    NCLINK_TRY(broker.duration("reconnect_min_ms", s.reconnect_min));
    NCLINK_TRY(broker.duration("reconnect_max_ms", s.reconnect_max));
    if (s.connect_timeout.count() == 0) return broker.fail(ErrorCode::value_type, "connect_timeout_ms", "must be at least 1");
    if (s.reconnect_min.count() == 0) return broker.fail(ErrorCode::value_type, "reconnect_min_ms", "must be at least 1");
    if (s.reconnect_max < s.reconnect_min)
        return broker.fail(ErrorCode::value_type, "reconnect_max_ms", "must be at least reconnect_min_ms");
    NCLINK_TRY(read_tls(broker, s.tls));
    NCLINK_TRY(read_failover(broker, s));  // last: the "valid keys" list keeps its order
    return ok_result();
}

}  // namespace nclink::transport_detail
