// keep_freed_heap(): the uploader's burst pattern stops faulting its pages in
// again once freed memory is kept. Each test case runs in its own process
// (ctest), so the process-wide policy of one never reaches another.
#include <nclink/heap.hpp>

#include "core/heap_release.hpp"
#include "support/heap_cycle.hpp"

#include <unistd.h>

#include <fstream>
#include <memory>
#include <vector>

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

namespace {
// Resident bytes of this process (/proc/self/statm, second field).
long long resident_bytes() {
    std::ifstream statm("/proc/self/statm");
    long long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * ::sysconf(_SC_PAGESIZE);
}
}  // namespace

TEST_CASE("release_freed_heap gives back freed memory inside the heap, which trimming never reaches") {
    if (test::sanitized_allocator()) {
        CHECK_FALSE(core_detail::release_freed_heap(0));
        return;
    }
    REQUIRE(keep_freed_heap(max_heap_keep_bytes));  // as an adapter sets it: no trimming of its own
    // 24 MB in 4 kB blocks, written, then all freed but the last: the free
    // memory lies below a block in use, where a heap is never trimmed.
    std::vector<std::unique_ptr<char[]>> blocks;
    for (int i = 0; i < 6 * 1024; ++i) {
        blocks.emplace_back(new char[4096]);
        std::memset(blocks.back().get(), 1, 4096);
    }
    auto last = std::move(blocks.back());
    blocks.pop_back();
    blocks.clear();
    const long long held = resident_bytes();
    REQUIRE(core_detail::release_freed_heap(0));
    const long long after = resident_bytes();
    INFO("resident before " << held << " after " << after);
    CHECK(held - after > (16LL << 20));
}

TEST_CASE("the periodic heap release waits one period, then releases once per period") {
    int released = 0;
    core_detail::PeriodicHeapRelease release([&] { ++released; }, std::chrono::seconds(10));
    const auto t0 = core_detail::PeriodicHeapRelease::Time{} + std::chrono::hours(1);
    auto next = release.poll(t0);  // added: the start is under way
    CHECK(released == 0);
    CHECK(next == t0 + std::chrono::seconds(10));
    next = release.poll(next);
    CHECK(released == 1);
    CHECK(next == t0 + std::chrono::seconds(20));
    release.poll(next);
    CHECK(released == 2);
}
