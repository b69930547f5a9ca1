// Counts the page faults of the allocation pattern an uploader makes every
// upload interval: a burst of DTU-sized blocks written, then all freed. With
// glibc's default policy the freed top of the thread's heap goes back to the
// kernel after each burst and the next burst faults its pages in again;
// with keep_freed_heap() the later bursts reuse them (nclink/heap.hpp).
#pragma once

#include <sys/resource.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

namespace nclink::test {

/// Whether this build runs under a sanitizer's allocator (mallopt has no
/// effect there: the heap policy cannot be observed).
constexpr bool sanitized_allocator() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
    return true;
#else
    return false;
#endif
#else
    return false;
#endif
}

/// Sets glibc's initial thresholds (128 KiB to trim, 128 KiB to mmap) as a
/// program of its own would, so a case checking that the allocator is left
/// as the program set it does not depend on an adapter another case of the
/// same process started before it.
inline void set_initial_heap_policy() {
#if defined(__GLIBC__)
    mallopt(M_TRIM_THRESHOLD, 128 * 1024);
    mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
}

/// Blocks of a burst that keep_freed_heap() keeps: a thread's malloc arena
/// grows in sub-heaps of 64 MB on a 64-bit target but of 1 MB on a 32-bit
/// one (armhf), and glibc unmaps a sub-heap that falls wholly free whatever
/// the trim threshold: there a kept burst must fit one sub-heap (8 x 64 kB).
constexpr std::size_t kKeptBurstBlocks = sizeof(long) >= 8 ? 32 : 8;

/// Minor page faults of bursts 2..`bursts` (the first one always faults),
/// each `blocks` blocks of `block_bytes`, on a thread of its own (its own
/// malloc arena, as an uploader has).
inline long faults_after_first_burst(int bursts = 5, std::size_t blocks = 32, std::size_t block_bytes = 64 * 1024) {
    long faults = 0;
    std::thread worker([&] {
        std::vector<void*> held(blocks);
        for (int b = 0; b < bursts; ++b) {
            rusage before{};
            getrusage(RUSAGE_THREAD, &before);
            for (auto& p : held) {
                p = std::malloc(block_bytes);
                std::memset(p, b + 1, block_bytes);
            }
            for (auto& p : held) std::free(p);
            rusage after{};
            getrusage(RUSAGE_THREAD, &after);
            if (b > 0) faults += after.ru_minflt - before.ru_minflt;
        }
    });
    worker.join();
    return faults;
}

}  // namespace nclink::test
