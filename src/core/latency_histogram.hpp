// A fixed-bucket latency histogram that any thread may observe into without a
// lock (relaxed atomics: each counter is exact, a snapshot taken while others
// observe may be off by the observations under way). Buckets follow the
// Prometheus convention: an observation lands in the first bucket whose upper
// bound it does not exceed.
#pragma once

#include <nclink/traffic_stats.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>

namespace nclink::core_detail {

/// Upper bounds in seconds: 100 us .. 10 s, the range of request round trips
/// on a broker (docs/metrics.md).
inline constexpr std::array<double, 16> kLatencyBoundsSeconds = {0.0001, 0.00025, 0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025,
                                                                 0.05,   0.1,     0.25,   0.5,   1,      2.5,   5,    10};

class LatencyHistogram {
public:
    void observe(std::chrono::nanoseconds elapsed) noexcept;
    std::uint64_t count() const noexcept { return count_.load(std::memory_order_relaxed); }
    HistogramSnapshot snapshot() const;

private:
    std::array<std::atomic<std::uint64_t>, kLatencyBoundsSeconds.size() + 1> buckets_{};
    std::atomic<std::uint64_t> count_{0};
    std::atomic<std::uint64_t> sum_ns_{0};
};

}  // namespace nclink::core_detail
