// The lock-free SPSC row ring: order, capacity, both full policies, and a
// two-thread stress run (also run under TSan).
#include "sampling/spsc_ring.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <thread>
#include <vector>

using namespace nclink;
using nclink::sampling_detail::FullPolicy;
using nclink::sampling_detail::SpscRowRing;

namespace {

bool push_row(SpscRowRing& ring, std::int64_t value) {
    SampleValue* row = ring.try_begin();
    if (row == nullptr) return false;
    for (std::size_t i = 0; i < ring.width(); ++i) row[i] = SampleValue::int64(value * 10 + static_cast<std::int64_t>(i));
    ring.commit(value * 1000, static_cast<std::uint64_t>(value));
    return true;
}

std::vector<std::int64_t> drain(SpscRowRing& ring) {
    std::vector<std::int64_t> out;
    const std::size_t n = ring.claim();
    for (std::size_t i = 0; i < n; ++i) {
        const SampleValue* row = ring.row(i);
        const std::int64_t v = row[0].as_int64() / 10;
        for (std::size_t c = 0; c < ring.width(); ++c) REQUIRE(row[c].as_int64() == v * 10 + static_cast<std::int64_t>(c));
        REQUIRE(ring.time_ns(i) == v * 1000);
        REQUIRE(ring.seq(i) == static_cast<std::uint64_t>(v));
        out.push_back(v);
    }
    ring.release(n);
    return out;
}

}  // namespace

TEST_CASE("ring capacity is a power of two and rows come out in order") {
    SpscRowRing ring(100, 3, FullPolicy::block);
    CHECK(ring.capacity() == 128);
    CHECK(ring.width() == 3);
    for (int i = 0; i < 50; ++i) REQUIRE(push_row(ring, i));
    CHECK(ring.size() == 50);
    const auto out = drain(ring);
    REQUIRE(out.size() == 50);
    for (int i = 0; i < 50; ++i) CHECK(out[static_cast<std::size_t>(i)] == i);
    CHECK(ring.size() == 0);
    // wrap around several times
    for (int round = 0; round < 5; ++round) {
        for (int i = 0; i < 100; ++i) REQUIRE(push_row(ring, round * 100 + i));
        const auto again = drain(ring);
        REQUIRE(again.size() == 100);
        CHECK(again.front() == round * 100);
        CHECK(again.back() == round * 100 + 99);
    }
}

TEST_CASE("ring block policy refuses when full and loses nothing") {
    SpscRowRing ring(4, 2, FullPolicy::block);
    for (int i = 0; i < 4; ++i) REQUIRE(push_row(ring, i));
    CHECK_FALSE(push_row(ring, 4));
    CHECK(ring.drops() == 0);  // refusing under block is not a drop: the producer keeps the row
    const auto out = drain(ring);
    CHECK(out == std::vector<std::int64_t>{0, 1, 2, 3});
    CHECK(push_row(ring, 4));
}

TEST_CASE("ring drop_oldest keeps the newest rows and counts drops") {
    SpscRowRing ring(4, 2, FullPolicy::drop_oldest);
    for (int i = 0; i < 10; ++i) REQUIRE(push_row(ring, i));
    CHECK(ring.drops() == 6);
    const auto out = drain(ring);
    CHECK(out == std::vector<std::int64_t>{6, 7, 8, 9});
}

TEST_CASE("ring drop_oldest refuses the new row while the consumer holds a claim") {
    SpscRowRing ring(4, 1, FullPolicy::drop_oldest);
    for (int i = 0; i < 4; ++i) REQUIRE(push_row(ring, i));
    const std::size_t n = ring.claim();
    REQUIRE(n == 4);
    // The rows being read must not be overwritten: the producer refuses instead.
    CHECK_FALSE(push_row(ring, 4));
    CHECK(ring.drops() == 1);
    CHECK(ring.row(0)->as_int64() == 0);
    ring.release(n);
    CHECK(push_row(ring, 5));
    CHECK(drain(ring) == std::vector<std::int64_t>{5});
}

TEST_CASE("ring partial release keeps the rest for the next claim") {
    SpscRowRing ring(8, 1, FullPolicy::block);
    for (int i = 0; i < 5; ++i) REQUIRE(push_row(ring, i));
    REQUIRE(ring.claim() == 5);
    ring.release(2);
    CHECK(drain(ring) == std::vector<std::int64_t>{2, 3, 4});
}

namespace {

// Producer pushes `total` rows; the consumer checks every row it sees is
// intact (all columns from the same push) and in increasing order.
void stress(FullPolicy policy, std::int64_t total) {
    SpscRowRing ring(64, 8, policy);
    std::atomic<bool> done{false};
    std::vector<std::int64_t> seen;
    seen.reserve(static_cast<std::size_t>(total));
    std::thread consumer([&] {
        for (;;) {
            const bool finished = done.load(std::memory_order_acquire);
            for (auto v : drain(ring)) seen.push_back(v);
            if (finished && ring.size() == 0) break;
            std::this_thread::yield();
        }
    });
    std::int64_t refused = 0;
    for (std::int64_t i = 0; i < total; ++i) {
        if (policy == FullPolicy::block) {
            while (!push_row(ring, i)) std::this_thread::yield();
        } else if (!push_row(ring, i)) {
            ++refused;
        }
    }
    done.store(true, std::memory_order_release);
    consumer.join();
    for (std::size_t i = 1; i < seen.size(); ++i) REQUIRE(seen[i] > seen[i - 1]);
    if (policy == FullPolicy::block) {
        REQUIRE(seen.size() == static_cast<std::size_t>(total));
        CHECK(ring.drops() == 0);
    } else {
        // Every row was either delivered or counted as dropped.
        CHECK(static_cast<std::uint64_t>(seen.size()) + ring.drops() == static_cast<std::uint64_t>(total));
        CHECK(ring.drops() >= static_cast<std::uint64_t>(refused));
    }
}

}  // namespace

TEST_CASE("ring two-thread stress with the block policy delivers every row intact") { stress(FullPolicy::block, 200000); }

TEST_CASE("ring two-thread stress with drop_oldest accounts for every row") { stress(FullPolicy::drop_oldest, 200000); }
