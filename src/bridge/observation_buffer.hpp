// The bridge's buffer of observations, as MTConnect 1.4 part 1 defines it
// (5.1.3): a fixed number of slots (bufferSize), every observation numbered
// with a 64-bit sequence that starts at 1 for an instance and never wraps,
// the oldest falling out when the buffer is full. firstSequence is the oldest
// still held, lastSequence the newest, and 5.1.3.6 asks for the last value of
// every item even when its observations left the buffer: `latest()` holds it,
// and `values_at()` rebuilds the values as of any sequence still buffered
// (current?at=, 5.5.2) from the values that fell out plus the buffer.
//
// Not synchronized: the bridge's store guards it with its mutex.
#pragma once

#include <nclink/json.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace nclink::bridge {

using ItemIndex = std::uint32_t;

struct Observation {
    std::uint64_t sequence = 0;
    std::int64_t time_ms = 0;  ///< ms since the epoch (the adapter's time, else arrival)
    ItemIndex item = 0;
    Json value;  ///< the NC-Link value; null = UNAVAILABLE
};

class ObservationBuffer {
public:
    /// `capacity` slots (at least 1).
    explicit ObservationBuffer(std::size_t capacity);

    /// Appends an observation and returns its sequence.
    std::uint64_t append(ItemIndex item, Json value, std::int64_t time_ms);

    std::size_t capacity() const noexcept { return slots_.size(); }
    std::size_t size() const noexcept { return size_; }
    /// Oldest sequence held; equals next_sequence() while empty (1 at start).
    std::uint64_t first_sequence() const noexcept { return next_ - size_; }
    /// Newest sequence held; first_sequence() - 1 while empty (0 at start).
    std::uint64_t last_sequence() const noexcept { return next_ - 1; }
    /// The sequence the next observation gets.
    std::uint64_t next_sequence() const noexcept { return next_; }

    /// The observation of `sequence`, nullptr when not in the buffer.
    const Observation* find(std::uint64_t sequence) const;
    /// The last observation of every item ever seen (index = item), also of
    /// items whose observations left the buffer; nullopt for items never seen.
    const std::vector<std::optional<Observation>>& latest() const noexcept { return latest_; }
    /// The last observation of every item with a sequence <= `at`
    /// (first_sequence() - 1 <= at <= last_sequence()).
    std::vector<std::optional<Observation>> values_at(std::uint64_t at) const;

    struct Range {
        std::vector<Observation> observations;
        std::uint64_t next_sequence = 0;  ///< the Header's nextSequence for this answer
    };
    /// Up to `count` observations from `from` on (first_sequence() <= from <=
    /// next_sequence(), count >= 1) that `wanted` accepts. nextSequence is one
    /// past the last observation examined when `count` were found, else
    /// next_sequence() (part 1 5.1.3.2: "from + count beyond the buffer").
    Range range(std::uint64_t from, std::size_t count, const std::function<bool(ItemIndex)>& wanted) const;

private:
    std::vector<Observation> slots_;
    std::size_t size_ = 0;
    std::uint64_t next_ = 1;
    std::vector<std::optional<Observation>> latest_;
    std::vector<std::optional<Observation>> fallen_;  ///< last value per item among observations evicted
};

}  // namespace nclink::bridge
