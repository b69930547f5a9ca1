// The sampling engine of one device: channels, one sampling thread for all of
// them (Scheduler), one uploader thread (Uploader) draining the channels'
// rings into Sample DTUs handed to a sink. See docs/sampling.md.
//
// Contract (what dynamic channels and the spool build on):
// - add_channel(): validates the spec (non-empty id and points, intervals >
//   0, upload >= sample, id unique in this engine: 410 when taken, 406 for bad
//   intervals, 412 for empty points); the channel runs from the next scheduler
//   pass (within ~20 ms). Data items that are SDK-held in the current model
//   (ModelState::sdk_held) are read from the store, others from the driver.
// - remove_channel(): returns false for an unknown id. The channel stops
//   producing at once; the rows it has sampled so far are still published by
//   the uploader (asynchronously, on its next pass) — removal loses nothing.
// - DtuSink is called on the uploader thread only, one DTU at a time, in
//   sample order per channel. Message.qos = spec.qos, retained = false.
// - set_model(): call after a Probe/Set; points are re-resolved against the
//   new model (store vs driver). Channels are not removed by it.
// - stats(): includes channels being removed until their last rows are out.
#pragma once

#include "feature/model_state.hpp"
#include "feature/sample_tap.hpp"
#include "feature/value_guard.hpp"
#include "core/poll_host.hpp"
#include "driver/driver_runner.hpp"
#include "sampling/sleeper.hpp"

#include <nclink/feature_config.hpp>
#include <nclink/clock.hpp>
#include <nclink/driver.hpp>
#include <nclink/log.hpp>
#include <nclink/result.hpp>
#include <nclink/sampling.hpp>
#include <nclink/transport.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nclink::sampling_detail {

using nclink::ChannelStats;

struct ChannelSpec {
    std::string id;                ///< channel id (model SAMPLE_CHANNEL id, or an allocated dynamic id)
    std::vector<PointRef> points;  ///< data items in column order
    double sample_interval_ms = 0;
    double upload_interval_ms = 0;
    std::string topic;  ///< Sample/{dev}/{channel} or Sample/{dev}/{ex}/{channel}
    int qos = 0;
    std::string owner_ex;  ///< "" for model channels, the ex_cid for dynamic ones
    bool push = false;     ///< push mode: rows come from push(), not from reads
};

/// Called on the uploader thread, one Sample DTU at a time.
using DtuSink = std::function<void(Message)>;

/// Everything the engine needs. References/pointers must outlive the engine.
struct EngineDeps {
    driver_detail::DriverRunner* driver = nullptr;  ///< may be null when every channel is push-mode or SDK-held
    std::function<std::shared_ptr<const feature_detail::ModelState>()> model;  ///< current snapshot (may return null)
    std::shared_ptr<const Clock> clock;                                        ///< monotonic deadlines + wall timestamps
    std::shared_ptr<Sleeper> sleeper;  ///< how the sampling/uploader threads wait (fake in tests)
    Logger logger;
    SamplingConfig config;
    std::string dev;  ///< guid in the DTUs
    DtuSink sink;
    feature_detail::SampleTap* tap = nullptr;  ///< optional: rows for watchers
    /// Optional: checks every sampled value against chapter 7 (a breaking
    /// value is sent as null and counted; value_guard.hpp). Null: unchecked.
    feature_detail::ValueGuard* values = nullptr;
    /// Optional, for benchmarks/diagnostics: called on the sampling thread for
    /// every tick (served or missed) with how late (ns) the pass that produced
    /// its row started after the tick's deadline. Must be quick.
    std::function<void(const std::string& channel, std::int64_t late_ns)> tick_observer;
    /// Optional (gateway mode, include/nclink/shared_threads.hpp): run the
    /// scheduler and the uploader on these shared threads instead of two of
    /// the engine's own. Only with a SystemClock (the host waits on real
    /// time); `sleeper` is then unused and the real-time options are not
    /// applied (logged).
    core_detail::PollHost* timers = nullptr;
    /// Optional (a single adapter, without `timers`): run the uploader as a
    /// pollable of this host (the adapter's background threads) instead of
    /// a thread of its own. The sampler keeps its own thread, its
    /// clock_nanosleep deadlines and its real-time options. Only with a
    /// SystemClock, as `timers`.
    core_detail::PollHost* uploader_host = nullptr;
    /// Where the channels' timelines sit in their interval's grid, a fraction
    /// in [0, 1): 0 puts the first tick on a multiple of the interval of the
    /// monotonic clock, 0.5 half an interval later. The channels of one
    /// engine keep one phase (they still share wake-ups); a gateway gives
    /// its adapters different ones so they do not all sample at once.
    double phase = 0;
};

class Scheduler;
class Uploader;
class ChannelCore;

class SamplingEngine {
public:
    explicit SamplingEngine(EngineDeps deps);
    ~SamplingEngine();  ///< stop()s
    SamplingEngine(const SamplingEngine&) = delete;
    SamplingEngine& operator=(const SamplingEngine&) = delete;

    /// Thread-safe, also while running.
    Result<void> add_channel(ChannelSpec spec);
    /// Thread-safe. False for an unknown id. Rows sampled so far are still published.
    bool remove_channel(const std::string& id);
    /// Thread-safe.
    std::vector<ChannelStats> stats() const;
    /// Rows lost to full rings, summed over the channels (stats()' drops,
    /// without copying the rest).
    std::uint64_t ring_drops() const;

    /// Starts the sampling and uploader threads, or adds both to
    /// EngineDeps::timers (idempotent).
    void start();
    /// Stops producing, publishes what every ring holds, joins both threads.
    /// Idempotent. Channels stay registered (start() resumes them).
    void stop();

    // ---- additions beyond the agreed API
    /// A Probe/Set installed a model: re-resolve points (store vs driver). Thread-safe.
    void set_model(std::shared_ptr<const feature_detail::ModelState> state);
    /// Handle for a push-mode channel (error 401 unknown id, 405 not push-mode). Thread-safe.
    Result<PushChannel> push_channel(const std::string& id) const;
    /// Ids of the channels (in add order). Thread-safe.
    std::vector<std::string> channel_ids() const;
    bool has_channel(const std::string& id) const;
    RealtimeStatus realtime() const;
    bool running() const;

    /// For tests on fake time without threads: run the sampling pass (every
    /// due tick at clock->now()) and the upload pass. Do not mix with start().
    void run_sampling_once();
    void run_upload_once(bool final_flush = false);

private:
    struct State;
    std::shared_ptr<State> state_;
};

}  // namespace nclink::sampling_detail
