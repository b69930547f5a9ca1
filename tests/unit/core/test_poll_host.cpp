#include "core/poll_host.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace nclink::core_detail;
using nclink::test::eventually;
using namespace std::chrono_literals;
using Time = PollHost::Time;

TEST_CASE("a pollable runs at once, then at the deadline it names, never before") {
    PollHost host(2, "t-host");
    std::mutex mutex;
    std::vector<Time> polled, asked;
    auto entry = host.add([&](Time now) {
        std::lock_guard<std::mutex> lock(mutex);
        polled.push_back(std::chrono::steady_clock::now());
        const Time next = now + 20ms;
        asked.push_back(next);
        return polled.size() < 4 ? next : Time::max();
    });
    REQUIRE(eventually([&] {
        std::lock_guard<std::mutex> lock(mutex);
        return polled.size() == 4;
    }));
    std::this_thread::sleep_for(60ms);  // Time::max(): not polled again
    std::lock_guard<std::mutex> lock(mutex);
    REQUIRE(polled.size() == 4);
    for (std::size_t i = 1; i < polled.size(); ++i) CHECK(polled[i] >= asked[i - 1]);
    host.remove(entry);
}

TEST_CASE("many pollables share few threads, each on its own period") {
    PollHost host(2, "t-host");
    REQUIRE(host.threads() == 2);
    constexpr int kEntries = 300;
    std::vector<std::atomic<int>> counts(kEntries);
    std::vector<PollHost::Handle> entries;
    for (int i = 0; i < kEntries; ++i)
        entries.push_back(host.add([&counts, i](Time now) {
            ++counts[i];
            return now + std::chrono::milliseconds(5 + i % 7);
        }));
    CHECK(host.size() == kEntries);
    REQUIRE(eventually([&] {
        for (auto& c : counts)
            if (c.load() < 5) return false;
        return true;
    }));
    for (auto& e : entries) host.remove(e);
    CHECK(host.size() == 0);
    std::vector<int> after;
    for (auto& c : counts) after.push_back(c.load());
    std::this_thread::sleep_for(30ms);
    for (int i = 0; i < kEntries; ++i) CHECK(counts[i].load() == after[i]);  // removed: never polled again
}

TEST_CASE("one pollable never runs on two threads at once, however often it is woken") {
    PollHost host(4, "t-host");
    std::atomic<int> inside{0}, overlaps{0}, polls{0};
    auto entry = host.add([&](Time now) {
        if (++inside > 1) ++overlaps;
        std::this_thread::sleep_for(200us);
        --inside;
        ++polls;
        return now + 1ms;
    });
    std::vector<std::thread> wakers;
    std::atomic<bool> stop{false};
    for (int i = 0; i < 3; ++i)
        wakers.emplace_back([&] {
            while (!stop) host.wake(entry);
        });
    REQUIRE(eventually([&] { return polls.load() >= 200; }));
    stop = true;
    for (auto& t : wakers) t.join();
    host.remove(entry);
    CHECK(overlaps == 0);
}

TEST_CASE("wake() runs a sleeping pollable now, and again after a poll it interrupted") {
    PollHost host(2, "t-host");
    std::atomic<int> polls{0};
    std::atomic<bool> hold{false}, holding{false};
    auto entry = host.add([&](Time) {
        ++polls;
        if (hold.exchange(false)) {
            holding = true;
            std::this_thread::sleep_for(30ms);
            holding = false;
        }
        return Time::max();  // only when woken
    });
    REQUIRE(eventually([&] { return polls == 1; }));
    std::this_thread::sleep_for(20ms);
    CHECK(polls == 1);
    hold = true;
    host.wake(entry);
    REQUIRE(eventually([&] { return holding.load(); }));
    host.wake(entry);  // while it runs: once more right after
    REQUIRE(eventually([&] { return polls == 3; }));
    std::this_thread::sleep_for(20ms);
    CHECK(polls == 3);
    host.remove(entry);
}

TEST_CASE("remove() waits for a running poll, from inside the poll it returns at once") {
    PollHost host(2, "t-host");
    SECTION("from another thread") {
        std::atomic<bool> started{false}, finished{false};
        auto entry = host.add([&](Time now) {
            started = true;
            std::this_thread::sleep_for(50ms);
            finished = true;
            return now;
        });
        REQUIRE(eventually([&] { return started.load(); }));
        host.remove(entry);
        CHECK(finished);
    }
    SECTION("from its own poll") {
        std::atomic<int> polls{0};
        PollHost::Handle entry;
        std::mutex mutex;
        {
            std::lock_guard<std::mutex> lock(mutex);
            entry = host.add([&](Time now) {
                ++polls;
                std::lock_guard<std::mutex> inner(mutex);
                host.remove(entry);
                return now;  // asks to run again: removed, so it does not
            });
        }
        REQUIRE(eventually([&] { return polls == 1; }));
        std::this_thread::sleep_for(20ms);
        CHECK(polls == 1);
        CHECK(host.size() == 0);
    }
}

TEST_CASE("a throwing pollable does not stop the others") {
    PollHost host(1, "t-host");
    std::atomic<int> throws{0}, good{0};
    auto bad = host.add([&](Time) -> Time {
        ++throws;
        throw std::runtime_error("broken");
    });
    auto fine = host.add([&](Time now) {
        ++good;
        return now + 1ms;
    });
    REQUIRE(eventually([&] { return good >= 20; }));
    CHECK(throws >= 1);  // polled again a second later, meanwhile the other runs
    host.remove(bad);
    host.remove(fine);
}

// With N threads all waiting for the next deadline, all N woke at it and
// all but one went back to sleep; a gateway's tens of thousands of polls a
// second made that the timer threads' main cost.
TEST_CASE("one thread waits for the next deadline: the others do not wake for every poll") {
    PollHost host(2, "t-host");
    std::vector<PollHost::Handle> entries;
    for (int i = 0; i < 4; ++i) {
        const Time phase = std::chrono::steady_clock::now() + std::chrono::microseconds(500 * i);
        entries.push_back(host.add([phase, first = true](Time now) mutable {
            if (first) {
                first = false;
                return phase;
            }
            return now + 2ms;
        }));
    }
    std::this_thread::sleep_for(300ms);
    for (auto& e : entries) host.remove(e);
    const auto polls = host.polls(), wakeups = host.wakeups();
    INFO("polls " << polls << ", wake-ups " << wakeups);
    REQUIRE(polls > 100);
    CHECK(static_cast<double>(wakeups) < 1.5 * static_cast<double>(polls));
}

TEST_CASE("a poll stuck far past the next deadline holds the others back by the backstop only") {
    PollHost host(2, "t-host");
    std::atomic<bool> release{false};
    std::atomic<int> fast{0};
    std::atomic<bool> stuck_started{false};
    auto stuck = host.add([&](Time now) {
        stuck_started = true;
        while (!release) std::this_thread::sleep_for(1ms);
        return now + 1h;
    });
    REQUIRE(eventually([&] { return stuck_started.load(); }));
    auto other = host.add([&](Time now) {
        ++fast;
        return now + 10ms;
    });
    // 300 ms at a 10 ms period while one poll is stuck the whole time.
    std::this_thread::sleep_for(300ms);
    CHECK(fast.load() >= 10);
    release = true;
    host.remove(other);
    host.remove(stuck);
}

// A gateway's machines come due together (their 100 ms channels share the
// grid): a second thread woken for every due item fought the first for the
// host's mutex all through each burst. A burst one thread gets through
// well within the backstop is now that thread's alone.
TEST_CASE("a burst of due pollables one thread keeps up with is served by that thread alone") {
    // A backstop no burst here comes near, even on a loaded box that
    // descheduled the serving thread for a while: only a second thread woken
    // for the due items themselves can serve part of a round.
    PollHost host(2, "t-host", std::chrono::seconds(2));
    constexpr int kItems = 40, kRounds = 15;
    const auto period = 30ms;
    // Far enough ahead that all are added before the first round is due (an
    // item added after its deadline goes to a free thread at once).
    const Time start = std::chrono::steady_clock::now() + 200ms;
    std::mutex mutex;
    std::map<int, std::set<std::thread::id>> threads_of_round;
    std::atomic<int> done{0};
    std::vector<PollHost::Handle> entries;
    for (int i = 0; i < kItems; ++i) {
        entries.push_back(host.add([&, round = -1](Time) mutable -> Time {
            if (round >= 0) {
                {
                    std::lock_guard<std::mutex> lock(mutex);
                    threads_of_round[round].insert(std::this_thread::get_id());
                }
                // ~40 us of work: a burst of 40 takes ~1.6 ms.
                const auto until = std::chrono::steady_clock::now() + 40us;
                while (std::chrono::steady_clock::now() < until) {
                }
            }
            if (++round == kRounds) {
                ++done;
                return Time::max();
            }
            return start + round * period;
        }));
    }
    REQUIRE(eventually([&] { return done.load() == kItems; }, 10s));
    for (auto& e : entries) host.remove(e);
    int alone = 0;
    for (const auto& [round, threads] : threads_of_round) alone += threads.size() == 1;
    INFO("rounds served by one thread: " << alone << " of " << threads_of_round.size());
    REQUIRE(threads_of_round.size() == kRounds);
    // With a second thread woken for every due item: 5-7 of 15 here.
    CHECK(alone == kRounds);
}
