// The process's heap policy while it streams samples.
//
// Why: glibc hands freed memory at the top of a thread's heap back to the
// kernel once more than 128 kB is free there (madvise), and the next
// allocation takes it back page by page. An uploader publishing a burst of
// Sample DTUs every upload interval, whose copies the MQTT library frees on
// its own thread at the PUBACKs, goes through that cycle every interval: the
// madvise flushes the TLB of every CPU running the process (an interrupt
// for each, the sampling thread's included) and each page comes back with
// a fault. Measured on a 2-vCPU VM at 1 M points/s (docs/performance.md, "The
// heap"): 56-147 madvise and up to ~5,000 page faults in 4 s with the
// cycle, none without it, and 25-30 % less CPU for the adapter.
//
// keep_freed_heap() sets glibc's trim and mmap thresholds, so that up to
// `bytes` of freed memory stays with the process for its next DTUs and
// blocks up to `bytes` come from the heap rather than from mmap. The process
// then keeps about its peak working set (plus up to `bytes` per malloc
// arena) instead of returning it between bursts. Adapter::start() calls it
// with AdapterConfig::heap_keep_bytes (default 32 MB, 0 = leave the
// allocator alone). It is process-wide: with several adapters in a process
// the last one started sets it.
//
// Threading: thread-safe (mallopt takes the allocator's locks).
#pragma once

#include <nclink/export.hpp>

#include <cstddef>

namespace nclink {

/// The largest value glibc accepts for the mmap threshold on 64-bit (half
/// its per-thread heap size); keep_freed_heap() caps it there.
inline constexpr std::size_t max_heap_keep_bytes = std::size_t{32} << 20;

/// Keeps up to `bytes` (capped at max_heap_keep_bytes) of freed memory for
/// reuse and serves blocks up to that size from the heap. False (nothing
/// changed) when `bytes` is 0 or the allocator does not take glibc's
/// mallopt settings: another C library, or a sanitizer's allocator.
NCLINK_API bool keep_freed_heap(std::size_t bytes);

}  // namespace nclink
