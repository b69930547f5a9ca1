// Freed memory inside the heap, handed back to the kernel now and then, in
// a process that serves many adapters (SharedThreads, docs/gateway.md).
//
// Why: keep_freed_heap() (nclink/heap.hpp) keeps freed memory for the next
// Sample DTUs, and glibc only ever trims the top of a heap. A gateway's start
// (every machine's registration, version and whole model sent at once to
// the agent, 34 kB each for a 300-point machine) leaves tens of MB free in
// the middle of the heaps, held for good: 1,000 such machines showed 348 MB
// resident, 300 MB after one malloc_trim (docs/performance.md). Released
// every kEvery, the start's peak goes back to the kernel, while the memory
// every upload reuses is given back and faulted in again only once per
// period, not once per upload (which is what heap.hpp avoids).
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <utility>

namespace nclink::core_detail {

/// glibc's malloc_trim(keep_top): gives back every whole free page inside
/// every malloc arena, and the top of the main heap beyond `keep_top`.
/// False where there is nothing to call (another C library, or a sanitizer's
/// allocator, whose memory glibc does not hold).
bool release_freed_heap(std::size_t keep_top);

/// A pollable (core/poll_host.hpp) calling `release` every `every`, the first
/// time one period after it is added: the time a gateway's start takes.
class PeriodicHeapRelease {
public:
    using Time = std::chrono::steady_clock::time_point;
    static constexpr std::chrono::seconds kEvery{10};

    explicit PeriodicHeapRelease(std::function<void()> release, std::chrono::milliseconds every = kEvery)
        : release_(std::move(release)), every_(every) {}

    /// Returns when to be polled next.
    Time poll(Time now) {
        if (started_) release_();
        started_ = true;
        return now + every_;
    }

private:
    std::function<void()> release_;
    std::chrono::milliseconds every_;
    bool started_ = false;
};

}  // namespace nclink::core_detail
