// Counts heap allocations through the C++ operator new, for tests that a
// path allocates nothing per row once warm. It replaces the global operator
// new of the test binary: include it in exactly one file of a binary.
// ASan and TSan replace it themselves: there NCLINK_TEST_COUNTS_ALLOCATIONS
// is 0 and nothing is counted (the test says so instead of asserting).
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define NCLINK_TEST_COUNTS_ALLOCATIONS 0
#else
#define NCLINK_TEST_COUNTS_ALLOCATIONS 1
#endif

namespace {
std::atomic<bool> g_counting{false};
std::atomic<std::uint64_t> g_allocations{0};
}  // namespace

#if NCLINK_TEST_COUNTS_ALLOCATIONS
// The default operator delete frees with free(): these pair with it.
void* operator new(std::size_t size) {
    if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
    if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
    throw std::bad_alloc();
}
#endif
