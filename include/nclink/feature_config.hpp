// Configuration of the features an adapter runs beside Query/Set/Probe:
// sampling (8.2.15-8.2.21), events (8.2.27-8.2.31) and methods (8.2.22-8.2.26).
// Sections "sampling", "events" and "methods" of the adapter configuration
// (docs/configuration.md); every key, its default and unit.
#pragma once

#include <nclink/export.hpp>
#include <chrono>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace nclink {

/// Sample channels (6.2.6, 8.2.15). JSON: "sampling": {...}. Keys: src/sampling/sampling_config.cpp.
struct NCLINK_API SamplingConfig {
    bool enabled = true;                    ///< "enabled": run the model's sample channels
    std::size_t max_dynamic_channels = 16;  ///< "max_dynamic_channels": more answers 415
    /// "push_channels": model channels whose rows the firmware pushes
    /// (Adapter::push_channel) instead of the SDK reading the driver.
    std::vector<std::string> push_channels;
    /// "qos": MQTT QoS (0 or 1) of the Sample DTUs of the model channels, and
    /// the default of dynamic channels (a Register/Sample may ask for 0 with
    /// privateInfo {"qos": 0}). QoS 1: nothing lost on the adapter's link to
    /// the broker (docs/delivery.md); QoS 0 DTUs in flight when the link
    /// breaks are gone.
    int qos = 1;
    /// "channel_qos": per model channel overrides of "qos", {"ch_fast": 1}.
    std::map<std::string, int> channel_qos;
    /// "full_policy": "drop_oldest" (default) or "block" when the uploader
    /// falls behind and a channel's ring is full (docs/sampling.md).
    std::string full_policy = "drop_oldest";
    /// "ring_periods": ring capacity in upload periods (rounded up to a power of two rows).
    double ring_periods = 4;
    std::size_t ring_max_rows = 65536;  ///< "ring_max_rows": cap of one ring
    /// "ring_min_ms": a ring holds at least this much time of rows at its
    /// channel's sample interval (and at least 4 rows), so a fast channel has
    /// room while the uploader is late and a slow one holds no more rows than
    /// its upload periods need (docs/sampling.md).
    double ring_min_ms = 250;
    /// "direct_reads": read the driver on the sampling thread (serialized with
    /// the driver's workers) instead of handing each read to a worker.
    bool direct_reads = true;
    int rt_priority = 0;      ///< "rt_priority": SCHED_FIFO priority of the sampling thread (0 = normal scheduling)
    long timer_slack_ns = 0;  ///< "timer_slack_ns": PR_SET_TIMERSLACK of the sampling thread (0 = leave default)
    int cpu = -1;             ///< "cpu": pin the sampling thread to this CPU (-1 = no pinning)
    /// "slice_us": under normal scheduling, the sampling thread asks the
    /// kernel for this time slice (Linux >= 6.12, EEVDF's per-task slice; no
    /// privilege needed). A thread with a shorter slice than the one running
    /// preempts it when it wakes, so a tick is not kept waiting behind the
    /// broker or the uploader for their whole slice (1.4 ms on 2 CPUs).
    /// 0 = the kernel's default; otherwise 100..100000.
    int slice_us = 100;
    /// "overrun_log_interval_ms": missed ticks are logged at most once per
    /// this interval (over all channels; the line sums up the bursts between).
    std::chrono::milliseconds overrun_log_interval{10000};
    std::size_t text_budget_bytes = 1u << 20;  ///< "text_budget_bytes": distinct text values kept per channel
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

/// Events (8.2.27-8.2.31). JSON: "events": {...}. Keys: src/events/events_config.cpp.
struct NCLINK_API EventsConfig {
    std::size_t max_events = 64;  ///< "max_events": registrations of all applications; more answers 416 (0 = none)
    /// "poll_interval_ms": how often watched items that no running sample
    /// channel reads are read (one driver call for all); 0 = never (values
    /// then come only from the sample stream and Adapter::notify_value).
    std::chrono::milliseconds poll_interval{100};
    /// "max_queued_values": values (sample rows, pushes) waiting for the events
    /// thread at most; beyond it new ones are dropped and counted.
    std::size_t max_queued_values = 65536;
    /// "qos": MQTT QoS (0 or 1) of Event DTUs (docs/delivery.md).
    int qos = 1;
};

/// Methods (8.2.32-8.2.36). JSON: "methods": {...}. Keys: src/methods/methods_config.cpp.
struct NCLINK_API MethodsConfig {
    /// "max_running": method runs at once (running or paused); one more Method/Call
    /// answers 417. 0 refuses every call. Each run has its own thread.
    std::size_t max_running = 4;
    /// "status_period_ms": Method/Status of each run at this period while it runs (> 0).
    std::chrono::milliseconds status_period{500};
    /// "stop_grace_ms": at Adapter::stop() running methods are cancelled and
    /// waited for this long; a method still in the driver then is abandoned.
    std::chrono::milliseconds stop_grace{2000};
};

}  // namespace nclink
