// Adapter configuration: every key, its default and unit. Loadable from a
// JSON file (docs/configuration.md shows a complete one) and overridable from
// code; load first, then assign the fields you want to force.
#pragma once

#include <nclink/export.hpp>
#include <nclink/feature_config.hpp>
#include <nclink/heap.hpp>
#include <nclink/http_limits.hpp>
#include <nclink/json.hpp>
#include <nclink/log.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/result.hpp>

#include <chrono>
#include <cstddef>
#include <optional>
#include <map>
#include <string>
#include <vector>

namespace nclink {

struct NCLINK_API AdapterConfig {
    // --- broker (JSON: "broker": {...}) ---
    std::string broker_url = "tcp://127.0.0.1:1883";  ///< "url"
    std::vector<std::string> failover_urls;           ///< "failover": brokers to fail over to (MqttOptions::failover_urls)
    std::string client_id;                            ///< "client_id"; default "nclink-adapter-<dev_uuid>"
    std::string username;                             ///< "username"
    std::string password;                             ///< "password"
    std::optional<MqttTlsOptions> tls;                ///< "tls": {"ca_file","cert_file","key_file","key_password","verify"}
    int mqtt_version = 4;                             ///< "mqtt_version": 4 (3.1.1), 5, or "auto" (0; MqttOptions::mqtt_version)
    std::chrono::seconds keep_alive{20};              ///< "keep_alive_s"
    std::chrono::milliseconds connect_timeout{5000};  ///< "connect_timeout_ms": a CONNECT without CONNACK for this long failed
    std::chrono::milliseconds reconnect_min{250};     ///< "reconnect_min_ms": first retry delay, doubled per failure
    std::chrono::milliseconds reconnect_max{10000};   ///< "reconnect_max_ms": retry delay cap (MqttOptions::reconnect_max)
    bool clean_session = true;                        ///< "clean_session"

    // --- model ---
    std::string model_path;  ///< "model": path of the probe file (required)
    std::string device_id;   ///< "device": which device of the model this adapter is ("" = the first)
    std::string dev_uuid;    ///< "dev_uuid": terminal id override ("" = device guid, else device id)
    bool strict = false;     ///< "strict": refuse models with conformance problems too
    std::string persistence_dir;  ///< "persistence_dir": where Probe/Set models and settable config values are kept ("" = not persisted)
    /// Check every value the driver returns against its item's chapter-7
    /// rule (docs/porting-guide.md, "Values the SDK checks"). Off only to
    /// measure what the checks cost (bench_sampling_throughput --no-value-checks).
    bool check_values = true;

    // --- wire ---
    bool standard_typo_topics = true;               ///< "standard_typo_topics": also publish Reigster/Unreigster response topics
    std::size_t offline_buffer_bytes = 8u << 20;    ///< "offline_buffer_bytes": kept while the broker is unreachable
    std::size_t max_in_flight = 64;                 ///< "max_in_flight": unacknowledged messages on the link
    std::chrono::milliseconds dedup_window{10000};  ///< "dedup_window_ms": a repeated @id within it is ignored
    std::size_t dedup_capacity = 4096;              ///< "dedup_capacity": @ids remembered at most

    // --- behaviour ---
    /// "request_threads": workers handling requests other than Query and
    /// Set (Probe, registrations, method calls, malformed DTUs' answers);
    /// Query and Set run on the driver's worker. One keeps a terminal at six
    /// threads (docs/footprint.md) but, under the kernel's normal scheduler,
    /// leaves a request flood about one point more null sample rows
    /// (docs/configuration.md); two is the default.
    std::size_t request_threads = 2;
    /// "max_pending_requests": requests waiting or being handled at most;
    /// beyond it requests are shed (dropped, counted as "shed") so a flood
    /// neither queues without bound nor starves sampling (docs/security.md).
    std::size_t max_pending_requests = 256;
    /// "max_request_bytes": a larger request payload is answered 404 unread
    /// (0 = no limit).
    std::size_t max_request_bytes = 1u << 20;
    std::chrono::milliseconds driver_timeout{1000};       ///< "driver_timeout_ms": deadline of one driver call (then 203)
    std::chrono::milliseconds register_timeout{3000};     ///< "register_timeout_ms": wait for Register/Response before retrying
    std::chrono::milliseconds register_retry_max{60000};  ///< "register_retry_max_ms": retry interval cap
    /// "application_lease_ms": an application from which no DTU came for this
    /// long is gone (8.2.18.3): its dynamic channels and events are released.
    /// Its Notify/State offline releases them at once. 0 = only on offline.
    std::chrono::milliseconds application_lease{300000};
    /// "heap_keep_bytes": freed memory the process keeps for its next Sample
    /// DTUs rather than handing it back to the kernel between uploads
    /// (nclink/heap.hpp says why; capped at 32 MB). Set at start(),
    /// process-wide. 0 = leave the allocator as the program set it.
    std::size_t heap_keep_bytes = max_heap_keep_bytes;

    // --- features (JSON objects of the same names) ---
    SamplingConfig sampling;
    EventsConfig events;
    MethodsConfig methods;

    // --- driver (JSON: "driver": {"plugin": path, "config": {...}}) ---
    std::string driver_plugin;  ///< plugin path ("" = the program links its driver)
    Json driver_config;         ///< handed to the driver's open()

    LogLevel log_level = LogLevel::info;  ///< "log_level": trace/debug/info/warn/error/off
    /// "metrics": {"http_workers", "http_header_timeout_ms", ...}: the HTTP
    /// limits of `nclink-sim --metrics` (the Adapter itself serves no HTTP;
    /// docs/metrics.md). A change takes a restart.
    HttpLimits metrics;
};

/// Reads a configuration object. Unknown keys are errors (typos must not pass
/// silently): 413 with the key's name; wrong types 405.
NCLINK_API Result<AdapterConfig> adapter_config_from_json(const Json& json, AdapterConfig base = {});
/// Reads a configuration file; relative paths in it (model, persistence_dir,
/// plugin, TLS files) are taken relative to the file's directory.
NCLINK_API Result<AdapterConfig> load_adapter_config(const std::string& path, AdapterConfig base = {});

}  // namespace nclink
