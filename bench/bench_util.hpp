// Small timing helpers shared by the benchmarks: steady clock, median,
// percentile, repeated runs. Benchmarks are programs, not tests: they print
// figures and always measure their baseline in the same run.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <sys/resource.h>

namespace nclink::bench {

/// Monotonic nanoseconds.
inline std::int64_t now_ns() noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// CPU seconds (user + system) of this whole process so far.
inline double process_cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

/// p in [0, 100]; nearest-rank on a sorted copy. 0 for an empty sample.
inline double percentile(std::vector<double> values, double p) {
    if (values.empty()) return 0;
    std::sort(values.begin(), values.end());
    const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(values.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(rank));
    const auto hi = static_cast<std::size_t>(std::ceil(rank));
    return values[lo] + (values[hi] - values[lo]) * (rank - static_cast<double>(lo));
}

inline double median(const std::vector<double>& values) { return percentile(values, 50); }
inline double minimum(const std::vector<double>& values) {
    return values.empty() ? 0 : *std::min_element(values.begin(), values.end());
}
inline double maximum(const std::vector<double>& values) {
    return values.empty() ? 0 : *std::max_element(values.begin(), values.end());
}

/// Keeps a value alive so the optimizer cannot drop the work producing it.
template <class T>
inline void do_not_optimize(const T& value) {
    asm volatile("" : : "r,m"(value) : "memory");
}

/// Runs `body` `iterations` times and returns the mean ns per iteration.
template <class Body>
double time_per_iteration(std::size_t iterations, Body&& body) {
    const auto start = now_ns();
    for (std::size_t i = 0; i < iterations; ++i) body();
    return static_cast<double>(now_ns() - start) / static_cast<double>(iterations);
}

}  // namespace nclink::bench
