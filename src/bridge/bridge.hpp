// nclink-bridge: NC-Link machines seen through MTConnect 1.4 REST, GB/T
// 18759.6 HTTP, SHDR and a live JSON API (docs/bridge.md). One Bridge owns
// the NC-Link client, the follower that feeds the store, the HTTP server
// (src/http) with every route, and the SHDR server.
//
// Threading: start() and stop() from one controlling thread; the parts run
// on their own threads (client dispatch, follower housekeeping, HTTP workers,
// SHDR connections). Accessors are thread-safe.
#pragma once

#include "bridge/bridge_store.hpp"

#include <nclink/config_reload.hpp>
#include <nclink/log.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/result.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nclink::bridge {

struct BridgeConfig {
    // broker section (as the adapter's and the agent's: src/transport/broker_config.hpp)
    std::string broker_url = "tcp://127.0.0.1:1883";
    std::vector<std::string> failover_urls;  ///< "failover": brokers to fail over to (MqttOptions::failover_urls)
    std::string client_id;                   ///< MQTT client id; empty = ex_cid
    std::string username;
    std::string password;
    int mqtt_version = 4;
    std::chrono::seconds keep_alive{20};
    std::chrono::milliseconds connect_timeout{5000};
    std::chrono::milliseconds reconnect_min{250};
    std::chrono::milliseconds reconnect_max{10000};
    std::optional<MqttTlsOptions> tls;

    std::string ex_cid = "nclink-bridge";  ///< the bridge's application terminal id
    std::vector<std::string> devices;      ///< empty: every adapter found
    std::string http_host = "127.0.0.1";
    int http_port = 5000;  ///< 0: any free port
    /// HTTP Basic credentials of every request (docs/dashboard.md "Security");
    /// required when http_host is not a loopback address.
    std::string http_username;
    std::string http_password;
    std::size_t http_workers = 16;
    std::size_t max_request_bytes = 64 * 1024;
    /// Slow and idle clients (docs/bridge.md "Slow and idle clients").
    std::size_t http_max_streams = 64;                    ///< SSE/MTConnect streams at once, each on its own thread
    std::chrono::milliseconds http_header_timeout{3000};  ///< a request head must be whole within this
    std::chrono::milliseconds http_keep_alive{5000};      ///< idle keep-alive connections closed after this
    std::chrono::milliseconds http_read_timeout{5000};    ///< a request body must arrive within this
    std::chrono::milliseconds http_write_timeout{5000};   ///< a client must take an answer within this
    std::size_t http_max_connections = 512;
    std::size_t http_max_connections_per_peer = 64;  ///< 0: no cap
    bool shdr_enabled = true;
    std::string shdr_host = "127.0.0.1";
    int shdr_port = 7878;  ///< 0: any free port
    std::size_t buffer_size = 131072;
    std::string sender = "nclink-bridge";
    std::chrono::milliseconds poll_interval{1000};
    std::chrono::milliseconds discovery_interval{30000};
    std::chrono::milliseconds request_timeout{3000};
    /// Silence after which an adapter is asked a Query of one item; no answer
    /// within request_timeout = UNAVAILABLE (follower.hpp). 0 = never.
    std::chrono::milliseconds adapter_liveness{10000};
    bool use_events = true;
    std::chrono::milliseconds heartbeat{10000};  ///< SSE ": ping" and SHDR PONG period
    LogLevel log_level = LogLevel::info;
};

/// Reads a configuration file (docs/bridge.md "Configuration"); unknown keys
/// are refused (413), like every nclink configuration file.
Result<BridgeConfig> load_bridge_config(const std::string& path, BridgeConfig defaults = {});
Result<BridgeConfig> bridge_config_from_json(const Json& json, BridgeConfig defaults = {});

/// "host:port" -> host, port; port 0..65535, host not empty.
Result<std::pair<std::string, int>> parse_host_port(const std::string& text);

class Bridge {
public:
    Bridge(BridgeConfig config, Logger logger);
    ~Bridge();  ///< stop()s
    Bridge(const Bridge&) = delete;
    Bridge& operator=(const Bridge&) = delete;

    /// Connects to the broker (in the background), binds HTTP and SHDR.
    /// Fails when a port cannot be bound or the client cannot be made.
    Result<void> start();
    void stop();

    /// A re-read configuration (SIGHUP, docs/bridge.md "Reload"): log_level
    /// takes effect at once; every other changed key is reported in
    /// restart_needed and keeps its running value until the next start (the
    /// sockets, the MQTT session and the MTConnect instance are made once).
    /// The keys are the schema's (docs/schema/bridge.schema.json). Thread-safe
    /// with the bridge serving; not concurrently with start() or stop().
    ConfigReload reload(const BridgeConfig& next);

    int http_port() const noexcept;
    int shdr_port() const noexcept;
    const BridgeStore& store() const noexcept;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace nclink::bridge
