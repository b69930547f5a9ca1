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
#include <unordered_map>
#include <vector>

namespace nclink::sampling_detail {

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
        // chapter 7 checks: each column's rule under the model of `rules_version`
        std::uint64_t rules_version = 0;
        std::shared_ptr<const feature_detail::ModelState> model;  // keeps `rules` alive
        // Per column; rule null = unchecked. A float64 inside [lo, hi]
        // passes inline, without a call into the rule (the bulk): a
        // single-valued number rule's bounds, (-inf, +inf) without a rule,
        // an empty range (lo > hi) for any other rule.
        std::vector<const ValueRule*> rules;
        std::vector<double> lo, hi;
        bool any_rule = false;
        // Verdicts on pre-serialized JSON by (column, interned text) (pull
        // channels only: their text lives as long as the channel). One map
        // per lane, not one per column: an empty map per point was 56 bytes
        // of a 300-point machine's memory each.
        struct VerdictKey {
            std::size_t column;
            const char* text;
            bool operator==(const VerdictKey& o) const { return column == o.column && text == o.text; }
        };
        struct VerdictHash {
            std::size_t operator()(const VerdictKey& k) const {
                return std::hash<const char*>()(k.text) ^ (k.column * 0x9e3779b97f4a7c15ULL);
            }
        };
        std::unordered_map<VerdictKey, ValueFault, VerdictHash> verdicts;
    };

    void refresh(Clock::Steady now);
    void drain(Lane& lane);
    /// Chapter 7 on drained rows: false when nothing is checked (checks off,
    /// no rule for any column); else the lane's rules are current.
    bool prepare_screen(Lane& lane);
    /// One row of lane.values after prepare_screen(): a value breaking its
    /// item's rule becomes null (a missed value), refused via deps.values.
    void screen_row(Lane& lane, SampleValue* row);
    /// One value the inline range test did not pass: its column's rule decides.
    void screen_value(Lane& lane, std::size_t column, SampleValue& value, bool stable_text);
    /// The full check of one value (everything but the inline number path).
    ValueFault check(Lane& lane, std::size_t column, const SampleValue& value, bool stable_text);
    void refuse(Lane& lane, const ValueRule& rule, ValueFault fault, SampleValue& value);
    void publish(Lane& lane);
    void publish_segment(Lane& lane, std::size_t first, std::size_t count);

    EngineShared& shared_;
    std::vector<Lane> lanes_;
    std::uint64_t seen_version_ = 0;
    // Starts small and grows to the largest DTU once: a 16 KB default per
    // machine was 2 % of a 300-point gateway machine's memory.
    SampleEncoder encoder_{1024};
};

}  // namespace nclink::sampling_detail
