// Time as an injectable dependency: timing logic (dedup windows, leases,
// retries, sampling deadlines) reads this interface, so tests run on a
// ManualClock instead of waiting.
#pragma once

#include <nclink/export.hpp>
#include <atomic>
#include <chrono>
#include <cstdint>

namespace nclink {

class NCLINK_API Clock {
public:
    using Steady = std::chrono::steady_clock::time_point;
    virtual ~Clock() = default;
    /// Monotonic time for intervals and deadlines.
    virtual Steady now() const = 0;
    /// Wall-clock milliseconds since the Unix epoch (UTC), for timestamps on the wire.
    virtual std::int64_t wall_ms() const = 0;
};

/// The real clocks. Thread-safe.
class NCLINK_API SystemClock final : public Clock {
public:
    Steady now() const override { return std::chrono::steady_clock::now(); }
    std::int64_t wall_ms() const override {
        return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
    }
};

/// A clock that moves only when told to. Thread-safe.
class NCLINK_API ManualClock final : public Clock {
public:
    explicit ManualClock(std::int64_t wall_ms_at_start = 1'700'000'000'000) : wall_start_(wall_ms_at_start) {}
    Steady now() const override { return Steady(std::chrono::nanoseconds(elapsed_ns_.load())); }
    std::int64_t wall_ms() const override { return wall_start_ + elapsed_ns_.load() / 1'000'000; }
    void advance(std::chrono::nanoseconds by) { elapsed_ns_ += by.count(); }

private:
    std::int64_t wall_start_;
    std::atomic<std::int64_t> elapsed_ns_{0};
};

}  // namespace nclink
