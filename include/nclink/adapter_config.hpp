// Adapter configuration: every key, its default and unit. Loadable from a
// JSON file (docs/configuration.md shows a complete one) and overridable from
// code; load first, then assign the fields you want to force.
#pragma once

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

/// Sample channels (issue 4). JSON: "sampling": {...}. Keys: src/sampling/sampling_config.cpp.
struct SamplingConfig {
    bool enabled = true;                       ///< "enabled": run the model's sample channels
    std::size_t max_dynamic_channels = 16;     ///< "max_dynamic_channels": more answers 415
    /// "push_channels": model channels whose rows the firmware pushes
    /// (Adapter::push_channel) instead of the SDK reading the driver.
    std::vector<std::string> push_channels;
    /// "qos": MQTT QoS (0 or 1) of the model channels' Sample DTUs (WIRE.md: 0).
    int qos = 0;
    /// "channel_qos": per model channel overrides of "qos", {"ch_fast": 1}.
    std::map<std::string, int> channel_qos;
    /// "full_policy": "drop_oldest" (default) or "block" when the uploader
    /// falls behind and a channel's ring is full (docs/sampling.md).
    std::string full_policy = "drop_oldest";
    /// "ring_periods": ring capacity in upload periods (rounded up to a power of two rows).
    double ring_periods = 4;
    std::size_t ring_max_rows = 65536;        ///< "ring_max_rows": cap of one ring
    /// "direct_reads": read the driver on the sampling thread (serialized with
    /// the driver's workers) instead of handing each read to a worker.
    bool direct_reads = true;
    int rt_priority = 0;                      ///< "rt_priority": SCHED_FIFO priority of the sampling thread (0 = normal scheduling)
    long timer_slack_ns = 0;                  ///< "timer_slack_ns": PR_SET_TIMERSLACK of the sampling thread (0 = leave default)
    int cpu = -1;                             ///< "cpu": pin the sampling thread to this CPU (-1 = no pinning)
    /// "overrun_log_interval_ms": missed ticks are logged at most once per
    /// this interval (over all channels; the line sums up the bursts between).
    std::chrono::milliseconds overrun_log_interval{10000};
    std::size_t text_budget_bytes = 1u << 20; ///< "text_budget_bytes": distinct text values kept per channel
    /// "max_dtu_bytes": an upload period whose DTU would be larger is sent as
    /// several consecutive DTUs of about this size (0 = no limit). paho
    /// stalls on payloads beyond the socket buffer (docs/sampling.md).
    std::size_t max_dtu_bytes = 1u << 20;
    /// "stats_item": id of the SDK-provided data item a Query reads the
    /// adapter's statistics from ("" = none).
    std::string stats_item = "nclink_stats";
    // -- offline store-and-forward (docs/store-and-forward.md)
    /// "spool_memory_bytes": RAM for Sample DTUs produced while the broker is
    /// unreachable, replayed in order after reconnect (oldest dropped when
    /// full). 0 = no spool: those DTUs are dropped (counted).
    std::size_t spool_memory_bytes = 4u << 20;
    /// "spool_disk_bytes": disk budget under <persistence_dir>/sample-spool
    /// once RAM is half full; also keeps the spool across a restart.
    /// 0 (or no persistence_dir) = RAM only.
    std::size_t spool_disk_bytes = 0;
};

/// Events (issue 5). JSON: "events": {...}. Keys: src/events/events_config.cpp.
struct EventsConfig {
    std::size_t max_events = 64;                   ///< "max_events": registrations of all applications; more answers 416 (0 = none)
    /// "poll_interval_ms": how often watched items that no running sample
    /// channel reads are read (one driver call for all); 0 = never (values
    /// then come only from the sample stream and Adapter::notify_value).
    std::chrono::milliseconds poll_interval{100};
    /// "max_queued_values": values (sample rows, pushes) waiting for the events
    /// thread at most; beyond it new ones are dropped and counted.
    std::size_t max_queued_values = 65536;
};

/// Methods (issue 5). JSON: "methods": {...}. Keys: src/methods/methods_config.cpp.
struct MethodsConfig {
    /// "max_running": method runs at once (running or paused); one more Method/Call
    /// answers 417. 0 refuses every call. Each run has its own thread.
    std::size_t max_running = 4;
    /// "status_period_ms": Method/Status of each run at this period while it runs (> 0).
    std::chrono::milliseconds status_period{500};
    /// "stop_grace_ms": at Adapter::stop() running methods are cancelled and
    /// waited for this long; a method still in the driver then is abandoned.
    std::chrono::milliseconds stop_grace{2000};
};

struct AdapterConfig {
    // --- broker (JSON: "broker": {...}) ---
    std::string broker_url = "tcp://127.0.0.1:1883";  ///< "url"
    std::string client_id;               ///< "client_id"; default "nclink-adapter-<dev_uuid>"
    std::string username;                ///< "username"
    std::string password;                ///< "password"
    std::optional<MqttTlsOptions> tls;   ///< "tls": {"ca_file","cert_file","key_file","key_password","verify"}
    int mqtt_version = 4;                ///< "mqtt_version": 4 (3.1.1) or 5
    std::chrono::seconds keep_alive{20}; ///< "keep_alive_s"
    bool clean_session = true;           ///< "clean_session"

    // --- model ---
    std::string model_path;              ///< "model": path of the probe file (required)
    std::string device_id;               ///< "device": which device of the model this adapter is ("" = the first)
    std::string dev_uuid;                ///< "dev_uuid": terminal id override ("" = device guid, else device id)
    bool strict = false;                 ///< "strict": refuse models with conformance problems too
    std::string persistence_dir;         ///< "persistence_dir": where Probe/Set models and settable config values are kept ("" = not persisted)

    // --- wire ---
    bool standard_typo_topics = true;    ///< "standard_typo_topics": also publish Reigster/Unreigster response topics
    std::size_t offline_buffer_bytes = 8u << 20;  ///< "offline_buffer_bytes": kept while the broker is unreachable
    std::size_t max_in_flight = 64;      ///< "max_in_flight": unacknowledged messages on the link
    std::chrono::milliseconds dedup_window{10000};  ///< "dedup_window_ms": a repeated @id within it is ignored
    std::size_t dedup_capacity = 4096;   ///< "dedup_capacity": @ids remembered at most

    // --- behaviour ---
    std::size_t request_threads = 2;     ///< "request_threads": workers handling requests
    std::chrono::milliseconds driver_timeout{1000};   ///< "driver_timeout_ms": deadline of one driver call (then 203)
    std::chrono::milliseconds register_timeout{3000}; ///< "register_timeout_ms": wait for Register/Response before retrying
    std::chrono::milliseconds register_retry_max{60000}; ///< "register_retry_max_ms": retry interval cap
    /// "application_lease_ms": an application from which no DTU came for this
    /// long is gone (8.2.18.3): its dynamic channels and events are released.
    /// Its Notify/State offline releases them at once. 0 = only on offline.
    std::chrono::milliseconds application_lease{300000};

    // --- features (JSON objects of the same names) ---
    SamplingConfig sampling;
    EventsConfig events;
    MethodsConfig methods;

    // --- driver (JSON: "driver": {"plugin": path, "config": {...}}) ---
    std::string driver_plugin;           ///< plugin path ("" = the program links its driver)
    Json driver_config;                  ///< handed to the driver's open()

    LogLevel log_level = LogLevel::info; ///< "log_level": trace/debug/info/warn/error/off
};

/// Reads a configuration object. Unknown keys are errors (typos must not pass
/// silently): 413 with the key's name; wrong types 405.
Result<AdapterConfig> adapter_config_from_json(const Json& json, AdapterConfig base = {});
/// Reads a configuration file; relative paths in it (model, persistence_dir,
/// plugin, TLS files) are taken relative to the file's directory.
Result<AdapterConfig> load_adapter_config(const std::string& path, AdapterConfig base = {});

namespace detail {
// Each feature reads its own section (unknown keys refused like everywhere).
Result<void> read_sampling_config(const Json& section, SamplingConfig& out);
Result<void> read_events_config(const Json& section, EventsConfig& out);
Result<void> read_methods_config(const Json& section, MethodsConfig& out);
}  // namespace detail

std::optional<LogLevel> log_level_from_string(std::string_view text);

}  // namespace nclink
