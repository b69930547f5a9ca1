// The sampling thread's work: one Scheduler serves every pull-mode channel of
// a device with absolute deadlines (tick k of a channel is due at
// t0 + k * sampleInterval, so error never accumulates).
//
// Late-tick policy (docs/sampling.md):
// - A tick served late (its deadline passed, the next one not yet due) is
//   read now and stamped with its nominal time; the lateness goes into the
//   channel's histogram.
// - When a pass finds several ticks of a channel due, the older ones are
//   overruns: each still produces its row, all values null (nothing was read
//   at that instant), and is counted; only the newest due tick is read. So
//   rows stay at sampleInterval spacing and a column never shifts.
// - After a stall longer than one upload period, only the last upload
//   period's missed ticks get null rows; the earlier ones are skipped
//   (counted) and the uploader starts a new DTU after the gap.
// - A read that fails or times out gives null in its slot.
// - Overruns are logged once per burst, and at most once per
//   sampling.overrun_log_interval_ms over all channels: the line then sums
//   up the bursts since the previous one. The end of a burst is a debug line.
#pragma once

#include "sampling/engine_shared.hpp"

#include <nclink/clock.hpp>

#include <memory>
#include <set>
#include <string>
#include <vector>

namespace nclink::sampling_detail {

class Scheduler {
public:
    explicit Scheduler(EngineShared& shared) : shared_(shared) {}

    /// Serves every due tick at the clock's now; returns the earliest next
    /// deadline (now + 1 h when no channel runs). Sampling thread only.
    Clock::Steady poll();
    /// Drops every channel (stop): the next poll() re-anchors them.
    void reset();
    /// The shortest sample interval of the channels that read the driver, 0
    /// when none does. Sampling thread only.
    std::int64_t fastest_driver_interval_ns() const;

private:
    struct Lane {
        std::shared_ptr<ChannelCore> core;
        Clock::Steady t0{};
        std::int64_t wall0_ns = 0;
        std::uint64_t next_k = 0;
        std::uint64_t model_version = 0;
        // read plan: which columns come from the driver, which from the store
        std::vector<PointRef> driver_points;  // with the handles of the model's binding
        std::vector<std::size_t> driver_columns;
        std::uint64_t generation = 0;           // of that binding
        std::vector<std::size_t> null_columns;  // points the driver does not serve: always null
        std::vector<std::string> store_ids;
        std::vector<std::size_t> store_columns;
        std::shared_ptr<const feature_detail::ModelState> model;
        std::vector<Result<Json>> results;  // read() path
        std::vector<SampleValue> samples;   // read_samples() path, when columns are not the whole row
        bool typed = true;                  // the driver may implement read_samples()
        bool identity_columns = false;      // driver column i is row slot i
        bool in_burst = false;
        std::uint64_t burst_overruns = 0;
    };

    void refresh(Clock::Steady now);
    void plan(Lane& lane, const std::shared_ptr<const feature_detail::ModelState>& model, std::uint64_t version);
    /// Serves `lane` if due; returns its next deadline.
    Clock::Steady serve(Lane& lane, Clock::Steady now);
    bool produce_null_row(Lane& lane, std::uint64_t k);
    bool produce_read_row(Lane& lane, std::uint64_t k);
    /// Reads the driver's points of `lane` into their slots of `row`; returns
    /// how many are null.
    std::uint64_t read_driver_columns(Lane& lane, SampleValue* row);
    /// Logs the start of a burst of missed ticks, rate-limited.
    void report_burst(const ChannelCore& core, std::uint64_t missed, std::chrono::microseconds late, Clock::Steady now);
    std::int64_t row_time_ns(const Lane& lane, std::uint64_t k) const {
        return lane.wall0_ns + static_cast<std::int64_t>(k) * lane.core->sample_interval_ns();
    }

    EngineShared& shared_;
    std::vector<Lane> lanes_;
    std::uint64_t seen_version_ = 0;
    // overrun log rate limit
    bool reported_burst_ = false;
    Clock::Steady last_burst_report_{};
    std::uint64_t quiet_bursts_ = 0;
    std::set<std::string> quiet_channels_;
};

/// A driver/store value as a SampleValue (text kept alive by the channel).
SampleValue to_sample_value(const Json& value, ChannelCore& channel);

}  // namespace nclink::sampling_detail
