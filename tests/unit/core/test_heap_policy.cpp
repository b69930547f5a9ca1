// keep_freed_heap(): the uploader's burst pattern stops faulting its pages in
// again once freed memory is kept. Each test case runs in its own process
// (ctest), so the process-wide policy of one never reaches another.
#include <nclink/heap.hpp>

#include "support/heap_cycle.hpp"

#include <limits>

#include <catch2/catch.hpp>

using namespace nclink;

TEST_CASE("with glibc's default policy a burst after the first faults its pages in again") {
    if (test::sanitized_allocator()) {
        SUCCEED("the sanitizer's allocator has its own policy");
        return;
    }
    test::set_initial_heap_policy();  // whatever a case before it in this process did
    // 4 later bursts of 2 MB: 512 pages each when the heap is trimmed. This
    // is what the next test case removes; were it not so, that one would
    // prove nothing.
    CHECK(test::faults_after_first_burst() > 400);
}

TEST_CASE("after keep_freed_heap the later bursts reuse the pages") {
    const bool applied = keep_freed_heap(std::size_t{32} << 20);
    if (test::sanitized_allocator()) {
        SUCCEED("the sanitizer's allocator ignores mallopt");
        return;
    }
    REQUIRE(applied);
    CHECK(test::faults_after_first_burst(5, test::kKeptBurstBlocks) < 40);
}

TEST_CASE("keep_freed_heap caps the size and does nothing for 0") {
    CHECK_FALSE(keep_freed_heap(0));
    if (!test::sanitized_allocator()) {
        // Beyond glibc's largest mmap threshold (32 MB on 64-bit, 512 kB on
        // 32-bit) mallopt would refuse it: capped instead, so a large value
        // (and the 32 MB default on armhf) still takes effect.
        CHECK(keep_freed_heap(std::numeric_limits<std::size_t>::max()));
        CHECK(keep_freed_heap(max_heap_keep_bytes));
        CHECK(test::faults_after_first_burst(5, test::kKeptBurstBlocks) < 40);
    }
}
