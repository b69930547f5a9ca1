// The adapter's registration retry (registration.hpp): the same request
// again after a growing interval, each wait spread by a quarter of it either
// side so that machines which timed out together do not retry together.
#include "adapter/registration.hpp"

#include <nclink/clock.hpp>

#include <catch2/catch.hpp>

#include <set>

using namespace nclink;
using namespace nclink::adapter_detail;
using namespace std::chrono_literals;

namespace {

// Sends at the clock's time and ticks in 10 ms steps until the retry falls
// due; returns how long after the time-out it came.
std::chrono::milliseconds wait_after_timeout(Registration& r, ManualClock& clock) {
    r.sent("m-register", clock.now());
    clock.advance(3000ms);
    const auto timed_out = clock.now();
    REQUIRE(r.tick(clock.now(), true).gave_up.count() > 0);
    for (int i = 0; i < 10000; ++i) {
        if (r.tick(clock.now(), true).resend)
            return std::chrono::duration_cast<std::chrono::milliseconds>(clock.now() - timed_out);
        clock.advance(10ms);
    }
    FAIL("no retry");
    return {};
}

}  // namespace

TEST_CASE("registration retry: each wait lies within a quarter of its interval and machines draw apart") {
    std::set<long long> first_waits;
    for (std::uint64_t machine = 0; machine < 50; ++machine) {
        ManualClock clock;
        Registration r(3000ms, 60000ms, std::hash<std::string>{}("m-" + std::to_string(machine)));
        const auto first = wait_after_timeout(r, clock);
        CHECK(first >= 2250ms);
        CHECK(first <= 3750ms);
        first_waits.insert(first.count() / 100);  // 100 ms slots
        // Still no answer: the interval doubles (6 s), the wait is drawn again.
        const auto second = wait_after_timeout(r, clock);
        CHECK(second >= 4500ms);
        CHECK(second <= 7500ms);
    }
    // 50 machines that timed out together retry spread over 1.5 s.
    CHECK(first_waits.size() >= 8);
}

TEST_CASE("registration retry: the interval stops growing at retry_max and an answer resets it") {
    ManualClock clock;
    Registration r(1000ms, 4000ms, 7);
    for (int i = 0; i < 6; ++i) {
        const auto wait = wait_after_timeout(r, clock);
        CHECK(wait <= 4000ms);
    }
    CHECK(wait_after_timeout(r, clock) >= 3000ms);  // at the cap: three quarters of 4 s at least
    RegisterResponse ok;
    ok.msg_id = Json("m-register");
    ok.cli_uuid = "m";
    CHECK(r.answered(ok) == Registration::Answer::accepted);
    CHECK(r.registered());
    // Asked again later (a reconnect) and not answered: the first interval again.
    r.sent("m-register", clock.now());
    clock.advance(1000ms);
    const auto tick = r.tick(clock.now(), true);
    CHECK(tick.first_give_up);
    CHECK(tick.gave_up >= 750ms);
    CHECK(tick.gave_up <= 1250ms);
}
