// The uploader thread's work: drains every channel's ring into a pending
// batch (often enough that a ring never fills while the uploader keeps up),
// hands drained rows to the sample tap, and every uploadInterval encodes the
// batch as Sample DTU(s) and hands them to the sink.
//
// DTU shape (6.2.6.2, 8.2.15; docs/wire.md): rows in time order, one `data` column per
// channel point in the channel's order, beginTime = the first row's time.
// A batch is split into several DTUs where rows are missing (a gap in the
// sequence: dropped rows, skipped ticks), since a DTU's rows are implicitly
// sampleInterval apart; at 2 upload periods of rows; and at about
// sampling.max_dtu_bytes (judged from the channel's previous DTU), to bound
// a DTU.
#pragma once

#include "sampling/engine_shared.hpp"

#include <nclink/sample_encoder.hpp>

#include <memory>
#include <vector>

namespace nclink::detail {

class Uploader {
public:
    explicit Uploader(EngineShared& shared) : shared_(shared) {}

    /// Drains and publishes what is due at the clock's now (everything when
    /// `final_flush`); returns the next time it has work. Uploader thread only.
    Clock::Steady poll(bool final_flush);

private:
    struct Lane {
        std::shared_ptr<ChannelCore> core;
        Clock::Steady next_publish{};
        Clock::Steady next_drain{};
        std::chrono::nanoseconds drain_period{};
        // pending rows, row-major
        std::vector<SampleValue> values;
        std::vector<std::int64_t> times;
        std::vector<std::uint64_t> seqs;
        double bytes_per_row = 0;  // of the last DTU (0 = none yet)
    };

    void refresh(Clock::Steady now);
    void drain(Lane& lane);
    void publish(Lane& lane);
    void publish_segment(Lane& lane, std::size_t first, std::size_t count);

    EngineShared& shared_;
    std::vector<Lane> lanes_;
    std::uint64_t seen_version_ = 0;
    SampleEncoder encoder_;
    std::vector<SampleValue> columns_;
};

}  // namespace nclink::detail
