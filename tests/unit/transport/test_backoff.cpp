#include "transport/backoff.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace nclink::transport_detail;
using namespace std::chrono_literals;

TEST_CASE("reconnect waits are jittered over the second half of the back-off") {
    std::mt19937 rng(7);
    std::set<long> seen;
    for (int i = 0; i < 200; ++i) {
        const auto wait = jittered(1000ms, rng);
        CHECK(wait >= 500ms);
        CHECK(wait <= 1000ms);
        seen.insert(static_cast<long>(wait.count()));
    }
    // Terminals dropped together do not retry together.
    CHECK(seen.size() > 100);
    CHECK(jittered(1ms, rng) == 1ms);
    CHECK(jittered(0ms, rng) == 0ms);
}
