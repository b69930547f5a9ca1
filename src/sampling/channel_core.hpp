// One sample channel as the engine runs it: its spec, its ring, its counters
// and the text its rows borrow. Shared (shared_ptr) by the engine, the
// sampling thread, the uploader and PushChannel handles, so a handle outliving
// the channel or the engine is harmless.
//
// Who writes what:
// - the producer (sampling thread for pull channels, the push() caller for
//   push channels): the ring's producer side, rows_sampled, overruns,
//   skipped_ticks, null_values (pull), lateness, texts;
// - the uploader: the ring's consumer side, rows_published, dtus_published;
// - the engine (under its mutex): open/removed/producer_done.
#pragma once

#include "sampling/spsc_ring.hpp"
#include "sampling/sampling_engine.hpp"

#include <nclink/json.hpp>

#include <array>
#include <atomic>
#include <mutex>
#include <string>
#include <unordered_set>

namespace nclink::sampling_detail {

class ChannelCore {
public:
    ChannelCore(ChannelSpec spec, std::size_t ring_capacity, FullPolicy policy, std::size_t text_budget_bytes)
        : spec_(std::move(spec)),
          ring_(ring_capacity, spec_.points.size(), policy),
          sample_interval_ns_(static_cast<std::int64_t>(spec_.sample_interval_ms * 1e6 + 0.5)),
          upload_interval_ns_(static_cast<std::int64_t>(spec_.upload_interval_ms * 1e6 + 0.5)),
          text_budget_(text_budget_bytes) {}

    const ChannelSpec& spec() const noexcept { return spec_; }
    /// The item id of a column (the spec's points, in column order).
    const std::string& id(std::size_t column) const { return spec_.points[column].id; }
    /// The columns' ids as one vector, for the sample tap's observers. Built
    /// on the first call (any thread): a gateway machine without watchers
    /// does not keep a second copy of its ids (docs/performance.md).
    const std::vector<std::string>& ids() const {
        std::call_once(ids_made_, [this] {
            ids_.reserve(spec_.points.size());
            for (const auto& p : spec_.points) ids_.push_back(p.id);
        });
        return ids_;
    }
    SpscRowRing& ring() noexcept { return ring_; }
    std::int64_t sample_interval_ns() const noexcept { return sample_interval_ns_; }
    std::int64_t upload_interval_ns() const noexcept { return upload_interval_ns_; }
    /// Rows one upload period holds (at least 1).
    std::size_t rows_per_upload() const noexcept {
        const auto n = sample_interval_ns_ > 0 ? upload_interval_ns_ / sample_interval_ns_ : 1;
        return n < 1 ? 1 : static_cast<std::size_t>(n);
    }

    /// Push-mode producer path (PushChannel::push). Wait-free.
    bool push(const SampleValue* values, std::size_t count, std::int64_t time_ns) noexcept {
        if (count != ring_.width() || !open_.load(std::memory_order_acquire)) return false;
        const std::uint64_t seq = push_seq_++;
        SampleValue* slot = ring_.try_begin();
        if (slot == nullptr) return false;  // counted in ring drops
        for (std::size_t i = 0; i < count; ++i) slot[i] = values[i];
        ring_.commit(time_ns, seq);
        rows_sampled.add();
        return true;
    }

    /// Text of a read value, kept alive for the channel's life (interned: a
    /// STATUS item repeats few strings). Producer thread only. Null when the
    /// budget is exhausted (counted as a null value).
    SampleValue intern_text(std::string_view text, bool json) {
        lookup_.assign(text.data(), text.size());  // C++17 sets have no string_view lookup
        auto found = texts_.find(lookup_);
        if (found == texts_.end()) {
            if (text_bytes_ + text.size() > text_budget_) return SampleValue::null();
            text_bytes_ += text.size() + sizeof(std::string);
            found = texts_.insert(lookup_).first;
        }
        // unordered_set nodes never move: the view stays valid.
        return json ? SampleValue::json(*found) : SampleValue::text(*found);
    }

    /// Records how late a tick started.
    void record_lateness(std::int64_t late_ns) noexcept {
        const std::uint64_t us = late_ns > 0 ? static_cast<std::uint64_t>(late_ns / 1000) : 0;
        std::size_t bucket = 0;
        while (bucket < kLatenessBoundsUs.size() && us >= kLatenessBoundsUs[bucket]) ++bucket;
        lateness[bucket].add();
        if (us > max_lateness_us.get()) max_lateness_us.add(us - max_lateness_us.get());
    }

    ChannelStats snapshot() const {
        ChannelStats s;
        s.id = spec_.id;
        s.topic = spec_.topic;
        s.owner_ex = spec_.owner_ex;
        s.push = spec_.push;
        s.sample_interval_ms = spec_.sample_interval_ms;
        s.upload_interval_ms = spec_.upload_interval_ms;
        s.points = spec_.points.size();
        s.ring_capacity = ring_.capacity();
        s.rows_sampled = rows_sampled.get();
        s.rows_published = rows_published.get();
        s.dtus_published = dtus_published.get();
        s.overruns = overruns.get();
        s.skipped_ticks = skipped_ticks.get();
        s.drops = ring_.drops();
        s.null_values = null_values.get();
        s.refused_values = refused_values.get();
        s.max_lateness_us = max_lateness_us.get();
        for (std::size_t i = 0; i < lateness.size(); ++i) s.lateness[i] = lateness[i].get();
        return s;
    }

    // ---- lifecycle flags (engine mutex writes; anyone reads)
    std::atomic<bool> open_{false};          // push() accepted
    std::atomic<bool> removed{false};        // remove_channel() was called
    std::atomic<bool> producer_done{false};  // the sampler will not write again (after removal)

    // ---- counters
    SingleWriterCounter rows_sampled, overruns, skipped_ticks, null_values, max_lateness_us;
    SingleWriterCounter rows_published, dtus_published, refused_values;  // refused: uploader (chapter 7)
    std::array<SingleWriterCounter, kLatenessBoundsUs.size() + 1> lateness;

private:
    const ChannelSpec spec_;
    mutable std::once_flag ids_made_;
    mutable std::vector<std::string> ids_;
    SpscRowRing ring_;
    const std::int64_t sample_interval_ns_;
    const std::int64_t upload_interval_ns_;
    std::uint64_t push_seq_ = 0;  // push producer only
    std::unordered_set<std::string> texts_;
    std::string lookup_;
    std::size_t text_bytes_ = 0;
    const std::size_t text_budget_;
};

}  // namespace nclink::sampling_detail
