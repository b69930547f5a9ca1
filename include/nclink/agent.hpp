// The agent of GB/T 41970-2022 (5.2.2, 8.2.1-8.2.6, 8.2.16, 8.3): runs beside
// any MQTT broker and adds what the standard asks of an agent on top of the
// broker's routing -- registration (Register/Request), discovery
// (Discovery/Request), state notification (Notify/State), the model-version
// cache (Probe/Version, cached Probe/Query for offline adapters), the
// connection-error answers DEV_UNREACHABLE and Timeout (8.3.4/8.3.5), and
// access control (301). docs/agent.md describes behaviour and configuration.
//
//   nclink::AgentConfig config = nclink::load_agent_config("agent.json").value();
//   nclink::Agent agent(config, logger);
//   if (auto started = agent.start(); !started) { ...started.error()... }
//   ... agent.stop();
//
// Threading: start() and stop() are called by the owner (once each, not
// concurrently). reload() may be called from any thread, but not while
// start() runs. stats(), terminals() and cached_model() are thread-safe.
// DTUs are handled on the transport's callback thread (quick, no I/O); one
// housekeeping thread runs timeouts, liveness and persistence.
#pragma once

#include <nclink/clock.hpp>
#include <nclink/config_reload.hpp>
#include <nclink/export.hpp>
#include <nclink/http_limits.hpp>
#include <nclink/json.hpp>
#include <nclink/log.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/result.hpp>
#include <nclink/traffic_stats.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace nclink {

/// What an application may do on an adapter (a bit set).
enum AccessRight : unsigned {
    access_none = 0,
    access_read = 1u << 0,    ///< Probe/Query, Query, dynamic sampling, events (and model Sample topics in the ACL)
    access_set = 1u << 1,     ///< Set, Probe/Set
    access_method = 1u << 2,  ///< Method/Call, Method/Control
    /// Reading the Method/Status, Method/Result (8.2.23, 8.2.24) and Event
    /// (8.2.31) DTUs of every application at the adapter, not only one's own
    /// (e.g. a dashboard). Granted by the broker ACL only (subscriptions never
    /// reach the agent), and only by name: "all" does not include it, as it
    /// shows other applications' traffic.
    access_watch = 1u << 3,
    access_all = access_read | access_set | access_method,  ///< the request rights; not watch
};

/// Which application may do what on which adapter. Precedence: the
/// application's entry for the adapter, else its "*" entry, else (listed
/// applications) nothing; applications not listed get `default_rights`.
struct NCLINK_API AccessPolicy {
    unsigned default_rights = access_all;                                 ///< "default"
    std::map<std::string, std::map<std::string, unsigned>> applications;  ///< "applications": ex -> (dev | "*") -> rights
};

/// A terminal named in the registration allowlist.
struct NCLINK_API TerminalEntry {
    std::string kind;      ///< "adapter", "application" or "" (learned from traffic)
    std::string password;  ///< "" = no credential; else Register/Request privateInfo.password must equal it
};

struct NCLINK_API RegistrationPolicy {
    bool open = true;                                ///< "open": false = only listed terminals may register (else 301)
    std::map<std::string, TerminalEntry> terminals;  ///< "terminals"
    std::size_t max_id_length = 128;                 ///< "max_id_length": longer ids get 414
    std::string id_pattern;                          ///< "id_pattern": ECMAScript regex the whole id must match ("" = any)
};

struct NCLINK_API AgentConfig {
    // --- broker (JSON "broker": {...}) ---
    std::string broker_url = "tcp://127.0.0.1:1883";  ///< "url"
    std::vector<std::string> failover_urls;           ///< "failover": brokers to fail over to (MqttOptions::failover_urls)
    std::string client_id;                            ///< "client_id"; default "<agent_id>-<random>" (unique per instance)
    std::string username;                             ///< "username"
    std::string password;                             ///< "password"
    std::optional<MqttTlsOptions> tls;                ///< "tls": {"ca_file","cert_file","key_file","key_password","verify"}
    int mqtt_version = 5;                             ///< "mqtt_version": 5, or 4 (3.1.1; mosquitto 2 still honours $share)
    std::chrono::seconds keep_alive{20};              ///< "keep_alive_s"
    std::chrono::milliseconds connect_timeout{5000};  ///< "connect_timeout_ms": a CONNECT without CONNACK for this long failed
    std::chrono::milliseconds reconnect_min{250};     ///< "reconnect_min_ms": first retry delay, doubled per failure
    std::chrono::milliseconds reconnect_max{10000};   ///< "reconnect_max_ms": retry delay cap (MqttOptions::reconnect_max)

    // --- identity and instances ---
    std::string agent_id = "nclink-agent";     ///< "agent_id": the agent's terminal id (ex of its own Probe/Query)
    std::string share_group = "nclink-agent";  ///< "share_group": $share group of answering subscriptions ("" = plain)
    /// "instances": how many agent instances split the work where the broker
    /// has no $share (share_group "", every instance subscribed plainly):
    /// each answers only the requests of the terminals whose id hashes to it
    /// (FNV-1a 32 mod instances; docs/agent.md "Several agents"). 1 = this
    /// instance answers everything.
    unsigned instances = 1;
    unsigned instance = 0;  ///< "instance": this instance's number, 0 .. instances-1

    // --- behaviour ---
    std::string state_dir;                            ///< "state_dir": registrations and cached models ("" = not persisted)
    std::chrono::milliseconds request_timeout{1500};  ///< "request_timeout_ms": then the agent answers 203
    /// "adapter_liveness_ms": an adapter from which no DTU came for this long is
    /// offline (3.22). 0 = trust its retained state and last will only.
    std::chrono::milliseconds adapter_liveness{0};
    /// "application_liveness_ms": the same for applications (which have no last
    /// will); 0 = never.
    std::chrono::milliseconds application_liveness{300000};
    bool observe_samples = true;  ///< "observe_samples": count Sample DTUs as signs of life
    /// "max_in_flight": the agent's messages handed to the broker and not yet
    /// acknowledged; later ones wait in order. It answers for the whole plant,
    /// so the window is wider than an adapter's 64 (docs/agent.md).
    std::size_t max_in_flight = 1000;
    /// "discovery_link": Discovery (8.2.3/8.2.4) on a connection of its own
    /// (client id: the agent's, then "-discovery"), so an application's
    /// Discovery never waits behind the terminals' traffic on the main one
    /// (docs/agent.md). Used when the agent makes its own links (not with
    /// use_transport() alone).
    bool discovery_link = true;
    std::chrono::milliseconds tick{20};  ///< "tick_ms": housekeeping period (timeouts, liveness)

    RegistrationPolicy registration;              ///< "registration": {...}
    AccessPolicy access;                          ///< "access": {...}
    std::string acl_agent_user = "nclink-agent";  ///< "acl": {"agent_user"}: broker user of the agents in the ACL file

    LogLevel log_level = LogLevel::info;  ///< "log_level"
    /// "metrics": {"http_workers", "http_header_timeout_ms", ...}: the HTTP
    /// limits of `nclink-agent --metrics` (the Agent itself serves no HTTP;
    /// docs/metrics.md). A change takes a restart.
    HttpLimits metrics;
};

/// Reads a configuration object; unknown keys 413, wrong types 405, a bad
/// id_pattern or right name 405, an unusable instances/instance/share_group
/// combination 101 (out of range).
NCLINK_API Result<AgentConfig> agent_config_from_json(const Json& json, AgentConfig base = {});
/// Reads a configuration file; a relative state_dir / TLS path is taken
/// relative to the file's directory.
NCLINK_API Result<AgentConfig> load_agent_config(const std::string& path, AgentConfig base = {});

/// A mosquitto acl_file that makes the broker enforce `config.access`
/// (docs/agent.md, "Broker ACL"). Broker user names must equal terminal ids.
NCLINK_API std::string mosquitto_acl(const AgentConfig& config);

/// Counters only grow.
struct NCLINK_API AgentStats {
    std::uint64_t registrations = 0;          ///< Register/Request accepted
    std::uint64_t registrations_refused = 0;  ///< answered NG (414, 301, malformed)
    /// resends of a request answered OK moments before, not answered again
    /// (docs/agent.md: the first answer is still on its way)
    std::uint64_t registrations_repeated = 0;
    std::uint64_t discoveries = 0;          ///< Discovery/Request answered
    std::uint64_t versions = 0;             ///< Probe/Version answered
    std::uint64_t models_fetched = 0;       ///< models stored after a version change
    std::uint64_t cached_probes = 0;        ///< Probe/Query answered from the cache (adapter offline)
    std::uint64_t unreachable = 0;          ///< requests answered DEV_UNREACHABLE
    std::uint64_t timeouts = 0;             ///< requests answered 203
    std::uint64_t denied = 0;               ///< requests answered 301 (access control)
    std::uint64_t state_notifications = 0;  ///< Notify/State published by the agent
    std::uint64_t malformed = 0;            ///< undecodable DTUs (answered NG where there is a topic to answer on)
    std::uint64_t ignored_retained = 0;     ///< requests ignored for their retain flag
    std::size_t pending = 0;                ///< requests waiting for the adapter's answer now
    std::uint64_t held_responses =
        0;  ///< responses for an offline application (its session keeps them; the state-machine text 42, 58)
    std::string state =
        "initial";  ///< "initial" before start, then "normal" (the state-machine text item 31; pairs: include/nclink/agent_state.hpp)
    TransportStats transport;
};

/// What the agent knows of one terminal.
struct NCLINK_API TerminalInfo {
    std::string id;
    std::string kind;  ///< "adapter", "application" or "" (not known yet)
    bool registered = false;
    std::string status;             ///< "online", "offline" or "unknown"
    std::int64_t last_alive_s = 0;  ///< wall seconds of the last DTU seen from it (0 = never)
    std::string version;            ///< adapters: the model version announced last
};

class NCLINK_API Agent {
public:
    explicit Agent(AgentConfig config, Logger logger = {});
    ~Agent();  ///< stop()s
    Agent(const Agent&) = delete;
    Agent& operator=(const Agent&) = delete;

    /// For tests and special links: use this transport instead of MQTT (set
    /// before start()). The agent owns it from then on.
    void use_transport(std::unique_ptr<Transport> transport);
    /// For tests and special links: the Discovery link (discovery_link) on
    /// this transport (set before start()). Without it an agent given
    /// use_transport() hears Discovery on that one transport.
    void use_discovery_transport(std::unique_ptr<Transport> transport);
    /// For tests: the clock of timeouts, liveness and timestamps.
    void use_clock(std::shared_ptr<const Clock> clock);

    /// Loads the persisted state, subscribes and connects (in the background).
    /// Fails on an unusable configuration or an unreadable state file.
    Result<void> start();
    /// Persists the state, flushes what is buffered, disconnects, joins.
    /// Idempotent.
    void stop(std::chrono::milliseconds flush_timeout = std::chrono::milliseconds(1000));

    /// Applies a new configuration to the running agent, as nclink-agent does
    /// on SIGHUP: registration, access, request_timeout_ms, the liveness
    /// times, acl and log_level (the logger's level, shared with every copy of
    /// it) take effect at once, for the next DTU; registrations already
    /// accepted stay. Changed keys of the broker section, agent_id,
    /// share_group, instances, instance, state_dir, observe_samples,
    /// max_in_flight, discovery_link and tick_ms are listed in
    /// restart_needed and keep their running value. Refuses (405, nothing
    /// applied) a configuration whose id_pattern is not a regular expression.
    /// Before start() every key is applied.
    Result<ConfigReload> reload(const AgentConfig& next);

    AgentStats stats() const;
    /// The $share group the agent answers through: share_group, or "" when
    /// start() found that the broker delivers nothing through shared
    /// subscriptions (RabbitMQ 3.10, ejabberd 23.01; docs/agent.md "Brokers
    /// without shared subscriptions") and it answers through plain ones.
    /// Stable after start(); thread-safe.
    std::string share_group_in_use() const;
    /// DTUs received and sent by topic kind (docs/metrics.md; rendered for
    /// Prometheus by agent_metrics.hpp). request_seconds stays empty.
    TrafficStats traffic_stats() const;
    std::vector<TerminalInfo> terminals() const;
    /// The cached model of an adapter, if any.
    std::optional<Json> cached_model(const std::string& dev) const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace nclink
