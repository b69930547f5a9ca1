// Lock-free single-producer/single-consumer ring of sample rows.
//
// A row is a fixed number (`width`, set at construction) of SampleValue plus
// a wall timestamp (ns) and a sequence number; rows are trivially copyable
// and live in one array allocated at construction: nothing is allocated
// afterwards. Capacity is a power of two (indices wrap by masking).
//
// Producer (sampling thread or a firmware push() caller):
//   SampleValue* row = ring.try_begin();   // nullptr: full and the policy refuses
//   ... fill row[0..width) ...
//   ring.commit(time_ns, seq);
// Consumer (uploader thread):
//   std::size_t n = ring.claim();          // rows readable: row(0..n)
//   ... copy them out ...
//   ring.release(n);                       // frees them; ends the claim
//
// Full policies
// - block: try_begin() returns nullptr while full; the producer decides what
//   to do (the sampler waits, a push() reports false). No row is ever lost
//   inside the ring.
// - drop_oldest: when full, the producer frees the oldest row itself by
//   advancing the consumer index with one compare-and-swap, so the newest row
//   always gets in and the oldest is counted in drops(). This is safe in SPSC
//   because the consumer index carries a "claimed" bit: the consumer sets it
//   (CAS) before reading rows and clears it when it releases them, and the
//   producer never advances the index while the bit is set. If the ring is
//   full at exactly the moment the consumer holds a claim (it only copies rows
//   out, microseconds), the producer refuses the new row instead (also counted
//   in drops()). Either way the producer makes one attempt: wait-free.
//   The consumer sees a gap in the sequence numbers where rows were dropped.
//
// Memory ordering: the producer publishes a row with a release store of head;
// the consumer acquires head after claiming. The consumer's release of the
// tail (release store) happens-after its reads of the rows it frees; the
// producer acquires the tail (load or CAS) before overwriting a slot.
#pragma once

#include <nclink/sample_value.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace nclink::sampling_detail {

enum class FullPolicy { drop_oldest, block };

/// A counter with one writer thread: plain load+store (no locked
/// instruction on the hot path), readable from any thread.
class SingleWriterCounter {
public:
    void add(std::uint64_t n = 1) noexcept {
        value_.store(value_.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
    }
    std::uint64_t get() const noexcept { return value_.load(std::memory_order_relaxed); }

private:
    std::atomic<std::uint64_t> value_{0};
};

class SpscRowRing {
public:
    /// `capacity` is rounded up to a power of two (at least 2); `width` >= 1.
    SpscRowRing(std::size_t capacity, std::size_t width, FullPolicy policy);
    SpscRowRing(const SpscRowRing&) = delete;
    SpscRowRing& operator=(const SpscRowRing&) = delete;

    std::size_t capacity() const noexcept { return capacity_; }
    std::size_t width() const noexcept { return width_; }
    FullPolicy policy() const noexcept { return policy_; }

    // ---- producer side (one thread at a time)

    /// The slot for the next row, or nullptr when the row cannot be queued
    /// (full under `block`; full during a consumer claim under `drop_oldest`,
    /// counted in drops()). Wait-free.
    SampleValue* try_begin() noexcept {
        const std::uint64_t head = head_.value.load(std::memory_order_relaxed);
        if (head - producer_.cached_tail >= capacity_) {
            const std::uint64_t word = tail_.value.load(std::memory_order_acquire);
            producer_.cached_tail = word >> 1;
            if (head - producer_.cached_tail >= capacity_) {
                if (policy_ == FullPolicy::block) return nullptr;
                // drop_oldest: free the oldest row unless the consumer is reading.
                std::uint64_t expected = word;
                if ((word & 1u) != 0 || !tail_.value.compare_exchange_strong(expected, word + 2, std::memory_order_acq_rel,
                                                                             std::memory_order_acquire)) {
                    drops_.add();
                    return nullptr;
                }
                producer_.cached_tail = (word >> 1) + 1;
                drops_.add();
            }
        }
        return slot(head);
    }
    /// Publishes the row try_begin() returned.
    void commit(std::int64_t time_ns, std::uint64_t seq) noexcept {
        const std::uint64_t head = head_.value.load(std::memory_order_relaxed);
        const std::size_t index = static_cast<std::size_t>(head & mask_);
        times_[index] = time_ns;
        seqs_[index] = seq;
        head_.value.store(head + 1, std::memory_order_release);
    }
    /// Rows lost to the full policy (producer-written).
    std::uint64_t drops() const noexcept { return drops_.get(); }

    // ---- consumer side (one thread at a time)

    /// Claims every readable row; returns how many (row(0) is the oldest).
    /// Call release() afterwards, also when it returned 0.
    std::size_t claim() noexcept {
        std::uint64_t word = tail_.value.load(std::memory_order_acquire);
        while (!tail_.value.compare_exchange_weak(word, word | 1u, std::memory_order_acq_rel, std::memory_order_acquire)) {
        }
        consumer_.claimed_tail = word >> 1;
        const std::uint64_t head = head_.value.load(std::memory_order_acquire);
        return static_cast<std::size_t>(head - consumer_.claimed_tail);
    }
    const SampleValue* row(std::size_t i) const noexcept { return slot(consumer_.claimed_tail + i); }
    std::int64_t time_ns(std::size_t i) const noexcept { return times_[(consumer_.claimed_tail + i) & mask_]; }
    std::uint64_t seq(std::size_t i) const noexcept { return seqs_[(consumer_.claimed_tail + i) & mask_]; }
    /// Frees the first `n` claimed rows and ends the claim.
    void release(std::size_t n) noexcept { tail_.value.store((consumer_.claimed_tail + n) << 1, std::memory_order_release); }

    /// Rows queued now (approximate while the other side runs). Any thread.
    std::size_t size() const noexcept {
        const std::uint64_t tail = tail_.value.load(std::memory_order_acquire) >> 1;
        const std::uint64_t head = head_.value.load(std::memory_order_acquire);
        return head >= tail ? static_cast<std::size_t>(head - tail) : 0;
    }

private:
    SampleValue* slot(std::uint64_t position) const noexcept {
        return values_.get() + static_cast<std::size_t>(position & mask_) * width_;
    }

    struct alignas(64) Index {
        std::atomic<std::uint64_t> value{0};
    };
    struct alignas(64) ProducerCache {
        std::uint64_t cached_tail = 0;
    };
    struct alignas(64) ConsumerCache {
        std::uint64_t claimed_tail = 0;
    };

    const std::size_t capacity_;
    const std::uint64_t mask_;
    const std::size_t width_;
    const FullPolicy policy_;
    std::unique_ptr<SampleValue[]> values_;
    std::unique_ptr<std::int64_t[]> times_;
    std::unique_ptr<std::uint64_t[]> seqs_;

    Index head_;              // written by the producer
    ProducerCache producer_;  // producer-only
    Index tail_;              // (index << 1) | claimed; written by the consumer, CAS by a dropping producer
    ConsumerCache consumer_;  // consumer-only
    SingleWriterCounter drops_;
};

/// The power of two >= n, at most the top bit of size_t (past it the
/// doubling would wrap to 0 and never end: n >= 2^31 on a 32-bit target).
inline std::size_t round_up_pow2(std::size_t n) noexcept {
    constexpr std::size_t top = ~(~std::size_t{0} >> 1);
    std::size_t p = 2;
    while (p < n && p < top) p <<= 1;
    return p;
}

/// Bytes of one ring of `capacity` rows (rounded up as the ring does) of
/// `width` values, or 0 when that does not fit size_t (the array sizes of
/// the constructor would wrap: a large ring_max_rows on a 32-bit target).
inline std::size_t ring_bytes(std::size_t capacity, std::size_t width) noexcept {
    const std::size_t rows = round_up_pow2(capacity);
    if (rows < capacity) return 0;
    const std::size_t values = width == 0 ? 1 : width;
    constexpr std::size_t max = ~std::size_t{0};
    if (values > (max - 2 * sizeof(std::uint64_t)) / sizeof(SampleValue)) return 0;
    const std::size_t per_row = values * sizeof(SampleValue) + sizeof(std::int64_t) + sizeof(std::uint64_t);
    if (rows > max / per_row) return 0;
    return rows * per_row;
}

inline SpscRowRing::SpscRowRing(std::size_t capacity, std::size_t width, FullPolicy policy)
    : capacity_(round_up_pow2(capacity)),
      mask_(capacity_ - 1),
      width_(width == 0 ? 1 : width),
      policy_(policy),
      values_(new SampleValue[capacity_ * width_]),
      times_(new std::int64_t[capacity_]()),
      seqs_(new std::uint64_t[capacity_]()) {}

}  // namespace nclink::sampling_detail
