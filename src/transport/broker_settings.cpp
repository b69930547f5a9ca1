#include "transport/broker_settings.hpp"

namespace nclink::transport_detail {

bool operator==(const BrokerSettings& a, const BrokerSettings& b) { return broker_changes(a, b).empty(); }

std::vector<std::string> broker_changes(const BrokerSettings& was, const BrokerSettings& now) {
    std::vector<std::string> out;
    auto key = [&](bool same, const char* name) {
        if (!same) out.emplace_back(name);
    };
    key(was.broker_url == now.broker_url, "url");
    key(was.failover_urls == now.failover_urls, "failover");
    key(was.client_id == now.client_id, "client_id");
    key(was.username == now.username, "username");
    key(was.password == now.password, "password");
    if (was.tls.has_value() != now.tls.has_value()) {
        out.emplace_back("tls");
    } else if (was.tls) {
        const MqttTlsOptions& a = *was.tls;
        const MqttTlsOptions& b = *now.tls;
        key(a.ca_file == b.ca_file, "tls.ca_file");
        key(a.cert_file == b.cert_file, "tls.cert_file");
        key(a.key_file == b.key_file, "tls.key_file");
        key(a.key_password == b.key_password, "tls.key_password");
        key(a.verify_server == b.verify_server, "tls.verify");
    }
    key(was.mqtt_version == now.mqtt_version, "mqtt_version");
    key(was.keep_alive == now.keep_alive, "keep_alive_s");
    key(was.connect_timeout == now.connect_timeout, "connect_timeout_ms");
    key(was.reconnect_min == now.reconnect_min, "reconnect_min_ms");
    key(was.reconnect_max == now.reconnect_max, "reconnect_max_ms");
    key(was.clean_session == now.clean_session, "clean_session");
    return out;
}

std::string describe_broker_changes(const std::vector<std::string>& changes) {
    std::string line;
    for (const std::string& change : changes) {
        if (!line.empty()) line += ", ";
        line += change;
    }
    return line;
}

std::vector<std::string> broker_reload_keys(const BrokerSettings& was, const BrokerSettings& now) {
    std::vector<std::string> keys;
    for (const std::string& change : broker_changes(was, now)) {
        std::string key = "broker." + (change.rfind("tls.", 0) == 0 ? std::string("tls") : change);
        if (keys.empty() || keys.back() != key) keys.push_back(std::move(key));
    }
    return keys;
}

}  // namespace nclink::transport_detail
