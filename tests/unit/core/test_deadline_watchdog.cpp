#include "core/deadline_watchdog.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

using namespace nclink::core_detail;
using Clock = std::chrono::steady_clock;

TEST_CASE("the watchdog runs each callback once, never before its deadline, earliest first") {
    // On a thread of its own, and as a pollable of a host (a single
    // adapter's background threads), with another pollable busy beside it.
    const bool on_host = GENERATE(false, true);
    CAPTURE(on_host);
    PollHost host(2, "test-host");
    std::atomic<int> busy_polls{0};
    auto busy = host.add([&](PollHost::Time now) {
        ++busy_polls;
        std::this_thread::sleep_for(std::chrono::milliseconds(3));
        return now;
    });
    DeadlineWatchdog watchdog(on_host ? &host : nullptr);
    std::mutex mutex;
    std::vector<int> order;
    std::vector<bool> on_time;
    const auto start = Clock::now();
    auto arm = [&](int tag, int ms) {
        const auto at = start + std::chrono::milliseconds(ms);
        REQUIRE(watchdog.arm(at, [&, tag, at] {
            std::lock_guard<std::mutex> lock(mutex);
            order.push_back(tag);
            on_time.push_back(Clock::now() >= at);
        }));
    };
    // Armed later-first, so the earlier ones must wake a sleeping watchdog.
    arm(3, 60);
    arm(2, 40);
    arm(1, 20);
    while (true) {
        std::lock_guard<std::mutex> lock(mutex);
        if (order.size() == 3) break;
    }
    CHECK(order == std::vector<int>{1, 2, 3});
    CHECK(on_time == std::vector<bool>{true, true, true});
    host.remove(busy);
    CHECK(busy_polls > 0);
}

TEST_CASE("stop drops what is armed and refuses new deadlines") {
    const bool on_host = GENERATE(false, true);
    CAPTURE(on_host);
    PollHost host(1, "test-host");
    std::atomic<int> ran{0};
    DeadlineWatchdog watchdog(on_host ? &host : nullptr);
    REQUIRE(watchdog.arm(Clock::now() + std::chrono::milliseconds(50), [&] { ++ran; }));
    watchdog.stop();
    CHECK_FALSE(watchdog.arm(Clock::now(), [&] { ++ran; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // past the first deadline
    CHECK(ran == 0);
    CHECK(host.size() == 0);  // a stopped watchdog leaves the host
}

TEST_CASE("a watchdog on a host costs it one pollable, and no thread") {
    PollHost host(1, "test-host");
    {
        DeadlineWatchdog watchdog(&host);
        CHECK(host.size() == 1);
        std::atomic<bool> ran{false};
        REQUIRE(watchdog.arm(Clock::now(), [&] { ran = true; }));
        while (!ran) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    CHECK(host.size() == 0);
}

TEST_CASE("an answer is claimed exactly once, by the worker or by the deadline") {
    SECTION("worker first") {
        AnswerClaim claim;
        CHECK(claim.claim_for_worker());
        CHECK_FALSE(claim.claim_for_deadline());
        CHECK_FALSE(claim.claim_for_worker());
    }
    SECTION("deadline first") {
        AnswerClaim claim;
        CHECK(claim.claim_for_deadline());
        CHECK_FALSE(claim.claim_for_worker());
    }
    SECTION("a deadline before the work started: the work is never done") {
        AnswerClaim claim;
        CHECK(claim.claim_deadline() == AnswerClaim::Deadline::before_start);
        CHECK_FALSE(claim.start_for_worker());
        CHECK_FALSE(claim.claim_for_worker());
    }
    SECTION("a deadline during the work: it answers, knowing the work may take effect") {
        AnswerClaim claim;
        CHECK(claim.start_for_worker());
        CHECK(claim.claim_deadline() == AnswerClaim::Deadline::during_work);
        CHECK_FALSE(claim.claim_for_worker());
    }
    SECTION("work started and answered in time: the deadline finds nothing") {
        AnswerClaim claim;
        CHECK(claim.start_for_worker());
        CHECK(claim.claim_for_worker());
        CHECK(claim.claim_deadline() == AnswerClaim::Deadline::lost);
        CHECK_FALSE(claim.start_for_worker());
    }
    SECTION("racing a started worker") {
        for (int round = 0; round < 200; ++round) {
            AnswerClaim claim;
            std::atomic<int> started{0}, wins{0};
            std::thread a([&] {
                if (claim.start_for_worker()) {
                    ++started;
                    wins += claim.claim_for_worker();
                }
            });
            std::thread b([&] { wins += claim.claim_for_deadline(); });
            a.join();
            b.join();
            REQUIRE(wins == 1);
        }
    }
    SECTION("racing threads") {
        for (int round = 0; round < 200; ++round) {
            AnswerClaim claim;
            std::atomic<int> wins{0};
            std::thread a([&] { wins += claim.claim_for_worker(); });
            std::thread b([&] { wins += claim.claim_for_deadline(); });
            a.join();
            b.join();
            REQUIRE(wins == 1);
        }
    }
}
