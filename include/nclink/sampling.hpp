// Sampling: statistics of the sample channels and push mode for firmware
// threads (docs/sampling.md).
//
// Push mode: a vendor whose real-time loop already has the values writes rows
// straight into a channel's ring instead of letting the SDK read the driver:
//
//   nclink::PushChannel ch = adapter.push_channel("ch_fast").value();  // once
//   ...
//   nclink::SampleValue row[3] = {SampleValue::float64(x), SampleValue::float64(y), SampleValue::int64(s)};
//   ch.push(row, 3);                 // in the servo loop: wait-free
//
// The channel must be listed in the configuration ("sampling": {"push_channels":
// ["ch_fast"]}); the SDK then never reads its items, it only batches the
// pushed rows and publishes them every uploadInterval exactly as in pull mode.
#pragma once

#include <nclink/export.hpp>
#include <nclink/result.hpp>
#include <nclink/sample_value.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nclink {

namespace sampling_detail {
class ChannelCore;  // the sampling module's own (src/sampling/channel_core.hpp)
}

/// Upper bounds (us, exclusive) of the lateness histogram buckets; the last
/// bucket counts everything at or above the last bound.
inline constexpr std::array<std::uint32_t, 11> kLatenessBoundsUs = {10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 100000};

/// Counters of one sample channel. Counters only grow while the channel runs.
struct NCLINK_API ChannelStats {
    std::string id;
    std::string topic;
    std::string owner_ex;  ///< "" for model channels
    bool push = false;     ///< rows come from PushChannel::push()
    double sample_interval_ms = 0;
    double upload_interval_ms = 0;
    std::size_t points = 0;            ///< columns per row
    std::size_t ring_capacity = 0;     ///< rows the ring holds
    std::uint64_t rows_sampled = 0;    ///< rows written into the ring (incl. rows of missed ticks)
    std::uint64_t rows_published = 0;  ///< rows handed to the transport in Sample DTUs
    std::uint64_t dtus_published = 0;
    std::uint64_t overruns = 0;        ///< ticks whose read could not start before the next tick was due
    std::uint64_t skipped_ticks = 0;   ///< ticks not produced at all after a very long stall (the DTU restarts)
    std::uint64_t drops = 0;           ///< rows lost because the ring was full
    std::uint64_t null_values = 0;     ///< values sent as null (failed/timed-out reads, missed ticks)
    std::uint64_t refused_values = 0;  ///< values sent as null for breaking chapter 7 (their item's rule)
    std::uint64_t max_lateness_us = 0;
    /// lateness[i] counts ticks that started less than kLatenessBoundsUs[i] us
    /// after their deadline (and at least the previous bound); the last entry
    /// counts the rest.
    std::array<std::uint64_t, kLatenessBoundsUs.size() + 1> lateness{};
};

/// Whether the real-time options of the sampling thread were granted.
struct NCLINK_API RealtimeStatus {
    int fifo_priority = 0;  ///< requested SCHED_FIFO priority (0 = not requested)
    bool fifo_granted = false;
    long timer_slack_ns = 0;  ///< requested timer slack (0 = not requested)
    bool timer_slack_granted = false;
    int cpu = -1;  ///< requested CPU (-1 = not requested)
    bool cpu_granted = false;
    int slice_us = 0;            ///< requested time slice (0 = not requested)
    bool slice_granted = false;  ///< false on kernels before 6.12 (no per-task slice) and under SCHED_FIFO
};

struct NCLINK_API SamplingStats {
    bool running = false;
    RealtimeStatus realtime;
    std::vector<ChannelStats> channels;
};

/// A handle to push rows into one push-mode channel. Cheap to copy; stays
/// valid (push() returns false) after the channel was removed or the adapter
/// stopped.
///
/// Thread-safety: push() may be called from ONE thread at a time per channel
/// (the ring is single-producer); the firmware's real-time thread is the
/// intended caller. Everything else is thread-safe.
class NCLINK_API PushChannel {
public:
    PushChannel() = default;
    explicit PushChannel(std::shared_ptr<sampling_detail::ChannelCore> core) : core_(std::move(core)) {}

    /// Appends one row: `values[i]` is the i-th point of the channel (the
    /// channel's `ids` order); `count` must equal points(). Timestamped with
    /// the wall clock now (clock_gettime(CLOCK_REALTIME), a vDSO read, no
    /// system call on Linux x86-64/arm64).
    /// Wait-free: never allocates, locks or sleeps. Returns false when the
    /// row was not queued (wrong count, channel gone, or the ring was full and
    /// the policy refuses: counted in ChannelStats::drops).
    /// Text/json values are borrowed until published: they must point to
    /// storage that lives for the channel's life (string literals).
    bool push(const SampleValue* values, std::size_t count) noexcept;
    /// Same with the caller's timestamp (wall clock, ns since the Unix epoch).
    bool push(const SampleValue* values, std::size_t count, std::int64_t time_ns) noexcept;

    /// Columns per row (0 for an empty handle).
    std::size_t points() const noexcept;
    const std::string& id() const noexcept;
    explicit operator bool() const noexcept { return static_cast<bool>(core_); }

private:
    std::shared_ptr<sampling_detail::ChannelCore> core_;
};

}  // namespace nclink
