// SerialWork: an owner's background work as a pollable of a shared PollHost
// (a gateway's work threads) or of a host of its own, in order either way.
#include "core/serial_work.hpp"

#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

using namespace nclink::core_detail;
using namespace std::chrono_literals;

namespace {

// A queue drained by serial work, as an outbox or a spool is.
struct Drained {
    std::mutex mutex;
    std::deque<int> queued;
    std::vector<int> done;
    std::atomic<int> inside{0};
    std::atomic<bool> overlapped{false};
    SerialWork work;

    void start(PollHost* host) {
        work.start(host, "test-serial", [this](PollHost::Time) {
            if (inside.fetch_add(1) != 0) overlapped = true;
            for (;;) {
                std::lock_guard<std::mutex> lock(mutex);
                if (queued.empty()) break;
                done.push_back(queued.front());
                queued.pop_front();
            }
            inside.fetch_sub(1);
            return PollHost::Time::max();
        });
    }
    void push(int n) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            queued.push_back(n);
        }
        work.wake();
    }
    std::size_t count() {
        std::lock_guard<std::mutex> lock(mutex);
        return done.size();
    }
};

std::vector<int> upto(int n) {
    std::vector<int> v;
    for (int i = 0; i < n; ++i) v.push_back(i);
    return v;
}

}  // namespace

TEST_CASE("serial work: owners on shared threads each run in order, never two turns at once") {
    PollHost host(2, "test-work");
    Drained a, b;
    a.start(&host);
    b.start(&host);
    CHECK(a.work.shared());
    // Two producers each, racing the turns.
    std::thread pa([&] {
        for (int i = 0; i < 2000; ++i) a.push(i);
    });
    std::thread pb([&] {
        for (int i = 0; i < 2000; ++i) b.push(i);
    });
    pa.join();
    pb.join();
    REQUIRE(nclink::test::eventually([&] { return a.count() == 2000 && b.count() == 2000; }, 10s));
    CHECK(a.done == upto(2000));
    CHECK(b.done == upto(2000));
    CHECK_FALSE(a.overlapped);
    CHECK_FALSE(b.overlapped);
    // Two owners, two threads: no thread each.
    CHECK(host.threads() == 2);
    CHECK(host.size() == 2);
}

TEST_CASE("serial work: one owner stopping leaves the shared threads serving the others") {
    PollHost host(1, "test-work");
    Drained a, b;
    a.start(&host);
    b.start(&host);
    a.work.stop();
    CHECK(host.size() == 1);
    a.push(1);  // a wake after stop does nothing
    b.push(7);
    REQUIRE(nclink::test::eventually([&] { return b.count() == 1; }, 5s));
    std::this_thread::sleep_for(20ms);
    CHECK(a.count() == 0);
}

TEST_CASE("serial work: without shared threads it runs on a thread of its own until stopped") {
    Drained a;
    a.start(nullptr);
    CHECK_FALSE(a.work.shared());
    for (int i = 0; i < 100; ++i) a.push(i);
    REQUIRE(nclink::test::eventually([&] { return a.count() == 100; }, 5s));
    CHECK(a.done == upto(100));
    a.work.stop();
    a.work.stop();  // idempotent
    a.push(100);
    std::this_thread::sleep_for(20ms);
    CHECK(a.count() == 100);
}
