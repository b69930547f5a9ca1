#include "transport/ack_watchdog.hpp"

#include <catch2/catch.hpp>

using namespace nclink::transport_detail;
using namespace std::chrono_literals;

namespace {
const AckWatchdog::Clock::time_point t0{std::chrono::hours(1)};
}

TEST_CASE("a window with messages in flight and no acknowledgement for the limit is stalled") {
    AckWatchdog w(10000ms);
    w.connected(t0);
    CHECK_FALSE(w.stalled(t0 + 100ms, 64));
    CHECK_FALSE(w.stalled(t0 + 9900ms, 64));
    CHECK(w.stalled(t0 + 10000ms, 64));
    CHECK(w.waited(t0 + 10000ms) == 10000ms);
    CHECK(w.stalled(t0 + 60000ms, 1));
}

TEST_CASE("every acknowledgement restarts the wait: a slow but moving window is never stalled") {
    AckWatchdog w(10000ms);
    w.connected(t0);
    // A broker acknowledging one message every 9 s for a minute, the window always full.
    for (int i = 1; i <= 7; ++i) {
        CHECK_FALSE(w.stalled(t0 + i * 9000ms - 100ms, 64));
        w.progress(t0 + i * 9000ms);
    }
    CHECK_FALSE(w.stalled(t0 + 63000ms + 9999ms, 64));
    CHECK(w.stalled(t0 + 63000ms + 10000ms, 64));
}

TEST_CASE("an empty window owes nothing: the wait starts when something is in flight again") {
    AckWatchdog w(10000ms);
    w.connected(t0);
    // Idle for an hour after the last acknowledgement.
    w.progress(t0 + 1s);
    CHECK_FALSE(w.stalled(t0 + 1h, 0));
    // A message goes out: it has the whole limit from the last empty check.
    CHECK_FALSE(w.stalled(t0 + 1h + 100ms, 1));
    CHECK_FALSE(w.stalled(t0 + 1h + 10000ms - 1ms, 1));
    CHECK(w.stalled(t0 + 1h + 10000ms, 1));
}

TEST_CASE("a new connection starts with nothing owed") {
    AckWatchdog w(10000ms);
    w.connected(t0);
    CHECK(w.stalled(t0 + 20s, 5));
    w.connected(t0 + 20s);  // reconnected; the 5 are sent again
    CHECK_FALSE(w.stalled(t0 + 29s, 5));
    CHECK(w.stalled(t0 + 30s, 5));
}

TEST_CASE("a limit of zero or less turns the check off") {
    AckWatchdog off(-1ms);
    off.connected(t0);
    CHECK_FALSE(off.stalled(t0 + 24h, 64));
    AckWatchdog zero(0ms);
    zero.connected(t0);
    CHECK_FALSE(zero.stalled(t0 + 24h, 64));
}
