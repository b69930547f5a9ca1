// Counts heap allocations per thread, so a bench can show what a steady
// state allocates and on which thread. Include it in exactly one translation
// unit of a bench program: it replaces malloc, calloc and realloc for the
// whole process (C++ operator new, paho and libmosquitto included) with
// glibc's own functions behind a counter. Counting costs one relaxed atomic
// add per allocation, and only between start() and stop().
//
// Not under ASan/TSan, which replace malloc themselves: available() is then
// false and nothing is counted.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <map>
#include <string>

#include <sys/syscall.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define NCLINK_BENCH_COUNT_ALLOCS 0
#else
#define NCLINK_BENCH_COUNT_ALLOCS 1
#endif

namespace nclink::bench::alloc {

struct Slot {
    std::atomic<long> tid{0};
    std::atomic<std::uint64_t> count{0};
};

constexpr int kSlots = 1024;
inline Slot g_slots[kSlots];
inline std::atomic<int> g_used{0};
inline std::atomic<bool> g_counting{false};
// A plain pointer in static TLS: reading it allocates nothing.
inline thread_local Slot* t_slot = nullptr;

inline void count() noexcept {
    if (!g_counting.load(std::memory_order_relaxed)) return;
    if (t_slot == nullptr) {
        const int i = g_used.fetch_add(1, std::memory_order_relaxed);
        if (i >= kSlots) return;  // more threads than slots: the rest go uncounted
        t_slot = &g_slots[i];
        t_slot->tid.store(::syscall(SYS_gettid), std::memory_order_relaxed);
    }
    t_slot->count.fetch_add(1, std::memory_order_relaxed);
}

inline bool available() noexcept { return NCLINK_BENCH_COUNT_ALLOCS != 0; }
inline void start() noexcept { g_counting.store(true, std::memory_order_release); }
inline void stop() noexcept { g_counting.store(false, std::memory_order_release); }
/// Every count back to 0 (between two measurements of one run).
inline void reset() noexcept {
    const int used = std::min(g_used.load(), kSlots);
    for (int i = 0; i < used; ++i) g_slots[i].count.store(0, std::memory_order_relaxed);
}

/// Allocations since start(), summed by thread name (a thread that has
/// exited since counts as "exited").
inline std::map<std::string, std::uint64_t> by_thread_name() {
    std::map<std::string, std::uint64_t> out;
    const int used = std::min(g_used.load(), kSlots);
    for (int i = 0; i < used; ++i) {
        const long tid = g_slots[i].tid.load();
        std::string name = "exited";
        std::ifstream comm("/proc/self/task/" + std::to_string(tid) + "/comm");
        if (comm) std::getline(comm, name);
        out[name] += g_slots[i].count.load();
    }
    return out;
}

}  // namespace nclink::bench::alloc

#if NCLINK_BENCH_COUNT_ALLOCS
extern "C" {
void* __libc_malloc(std::size_t) noexcept;
void* __libc_calloc(std::size_t, std::size_t) noexcept;
void* __libc_realloc(void*, std::size_t) noexcept;

// glibc's own allocator underneath: free(), posix_memalign() and the rest
// stay glibc's and see the same heap.
void* malloc(std::size_t size) noexcept {
    nclink::bench::alloc::count();
    return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) noexcept {
    nclink::bench::alloc::count();
    return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) noexcept {
    nclink::bench::alloc::count();
    return __libc_realloc(p, size);
}
}
#endif
