#include "core/latency_histogram.hpp"

#include <algorithm>

namespace nclink::core_detail {

void LatencyHistogram::observe(std::chrono::nanoseconds elapsed) noexcept {
    const auto ns = std::max<std::int64_t>(0, elapsed.count());
    const double seconds = static_cast<double>(ns) / 1e9;
    const auto it = std::lower_bound(kLatencyBoundsSeconds.begin(), kLatencyBoundsSeconds.end(), seconds);
    buckets_[static_cast<std::size_t>(it - kLatencyBoundsSeconds.begin())].fetch_add(1, std::memory_order_relaxed);
    sum_ns_.fetch_add(static_cast<std::uint64_t>(ns), std::memory_order_relaxed);
    count_.fetch_add(1, std::memory_order_relaxed);
}

HistogramSnapshot LatencyHistogram::snapshot() const {
    HistogramSnapshot s;
    s.upper_bounds.assign(kLatencyBoundsSeconds.begin(), kLatencyBoundsSeconds.end());
    s.counts.reserve(buckets_.size());
    for (const auto& b : buckets_) {
        s.counts.push_back(b.load(std::memory_order_relaxed));
        s.count += s.counts.back();
    }
    // The bucket counts are the truth for _count: read separately, count_
    // could disagree with the buckets while observations are under way.
    s.sum = static_cast<double>(sum_ns_.load(std::memory_order_relaxed)) / 1e9;
    return s;
}

}  // namespace nclink::core_detail
