// The broker settings every program's configuration carries (adapter, agent,
// bridge, gateway: the "broker" section, docs/configuration.md) as one value:
// the one place that says whether two of them are the same and names what
// differs, for the configuration reloads, and the one place that turns them
// into the transport's MqttOptions.
#pragma once

#include <nclink/mqtt_transport.hpp>

#include <chrono>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace nclink::transport_detail {

struct BrokerSettings {
    std::string broker_url = "tcp://127.0.0.1:1883";  ///< "url"
    std::vector<std::string> failover_urls;           ///< "failover"
    std::string client_id;                            ///< "client_id"
    std::string username;                             ///< "username"
    std::string password;                             ///< "password"
    std::optional<MqttTlsOptions> tls;                ///< "tls"
    int mqtt_version = 4;                             ///< "mqtt_version"
    std::chrono::seconds keep_alive{20};              ///< "keep_alive_s"
    std::chrono::milliseconds connect_timeout{5000};  ///< "connect_timeout_ms": a CONNECT without CONNACK for this long failed
    std::chrono::milliseconds reconnect_min{250};     ///< "reconnect_min_ms": first retry delay, doubled per failure
    std::chrono::milliseconds reconnect_max{10000};   ///< "reconnect_max_ms": retry delay cap (MqttOptions::reconnect_max)
    bool clean_session = true;                        ///< "clean_session" (adapter only; others keep the default)

    /// The broker settings of a configuration (AdapterConfig, AgentConfig,
    /// BridgeConfig) or of MqttOptions: the fields of the same names; a
    /// configuration without clean_session keeps the default (true).
    template <class Config>
    static BrokerSettings of(const Config& c);

    /// Sets the fields of the same names in `target` (MqttOptions, or a
    /// configuration) to these settings and leaves the others (last will,
    /// outbox, acknowledgement timeout) as they are; clean_session only where it exists.
    template <class Target>
    void apply_to(Target& target) const;
};

bool operator==(const BrokerSettings& a, const BrokerSettings& b);
inline bool operator!=(const BrokerSettings& a, const BrokerSettings& b) { return !(a == b); }

/// What differs between `was` and `now`, each named by its key in the broker
/// section of a configuration file, in the order the file documents them:
/// "url", "failover", "client_id", "username", "password", "tls" (TLS added or removed)
/// or "tls.ca_file", "tls.cert_file", "tls.key_file", "tls.key_password",
/// "tls.verify" (TLS kept, a file or check changed), "mqtt_version",
/// "keep_alive_s", "connect_timeout_ms", "reconnect_min_ms", "reconnect_max_ms",
/// "clean_session". Empty when they are equal.
std::vector<std::string> broker_changes(const BrokerSettings& was, const BrokerSettings& now);

/// The changes as one line for a person: "url, tls.ca_file"; "" when none.
std::string describe_broker_changes(const std::vector<std::string>& changes);

/// The changes as the keys a ConfigReload reports (docs/configuration.md,
/// "Reloading"): each prefixed "broker.", every "tls.*" folded into one
/// "broker.tls".
std::vector<std::string> broker_reload_keys(const BrokerSettings& was, const BrokerSettings& now);

namespace broker_settings_traits {
template <class C, class = void>
struct has_clean_session : std::false_type {};
template <class C>
struct has_clean_session<C, std::void_t<decltype(std::declval<const C&>().clean_session)>> : std::true_type {};
}  // namespace broker_settings_traits

template <class Config>
BrokerSettings BrokerSettings::of(const Config& c) {
    BrokerSettings s;
    s.broker_url = c.broker_url;
    s.failover_urls = c.failover_urls;
    s.client_id = c.client_id;
    s.username = c.username;
    s.password = c.password;
    s.tls = c.tls;
    s.mqtt_version = c.mqtt_version;
    s.keep_alive = c.keep_alive;
    s.connect_timeout = c.connect_timeout;
    s.reconnect_min = c.reconnect_min;
    s.reconnect_max = c.reconnect_max;
    if constexpr (broker_settings_traits::has_clean_session<Config>::value) s.clean_session = c.clean_session;
    return s;
}

template <class Target>
void BrokerSettings::apply_to(Target& t) const {
    t.broker_url = broker_url;
    t.failover_urls = failover_urls;
    t.client_id = client_id;
    t.username = username;
    t.password = password;
    t.tls = tls;
    t.mqtt_version = mqtt_version;
    t.keep_alive = keep_alive;
    t.connect_timeout = connect_timeout;
    t.reconnect_min = reconnect_min;
    t.reconnect_max = reconnect_max;
    if constexpr (broker_settings_traits::has_clean_session<Target>::value) t.clean_session = clean_session;
}

}  // namespace nclink::transport_detail
