// Runs a callback when a deadline passes, on the watchdog's own thread. Used
// where the thread doing a piece of work cannot itself give up on time (it is
// inside a driver call): the watchdog answers for it.
//
// Cheap to arm on a hot path: arming takes a mutex and a heap push, and wakes
// the watchdog only when the new deadline is earlier than the one it sleeps
// for. Entries are not removed when their work finishes early; the callback
// decides (typically by losing a race on an atomic claim) that it has nothing
// to do. So under steady load the watchdog wakes about once per deadline
// period, not once per arm.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <queue>
#include <thread>
#include <vector>

namespace nclink::detail {

class DeadlineWatchdog {
public:
    using Time = std::chrono::steady_clock::time_point;

    DeadlineWatchdog();
    ~DeadlineWatchdog();  ///< stop()s
    DeadlineWatchdog(const DeadlineWatchdog&) = delete;
    DeadlineWatchdog& operator=(const DeadlineWatchdog&) = delete;

    /// Thread-safe. `on_expiry` runs on the watchdog thread at or after `at`
    /// (never before), unless stop() comes first. False after stop().
    bool arm(Time at, std::function<void()> on_expiry);
    /// Drops what is armed and joins the thread. Idempotent; not from a callback.
    void stop();

private:
    struct Entry {
        Time at;
        std::function<void()> run;
        bool operator>(const Entry& other) const { return at > other.at; }
    };
    void loop();

    std::mutex mutex_;
    std::condition_variable wake_;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> entries_;
    Time sleeping_until_ = Time::max();
    bool stopping_ = false;
    std::thread thread_;
};

/// The one answer to a request, claimed either by the worker that did the
/// work or by the watchdog when the deadline passed first. Exactly one wins.
class AnswerClaim {
public:
    /// The worker: true when it may answer (the deadline has not claimed it).
    bool claim_for_worker() noexcept { return claim(kWorker); }
    /// The watchdog: true when the worker has not answered yet.
    bool claim_for_deadline() noexcept { return claim(kDeadline); }

private:
    static constexpr int kOpen = 0, kWorker = 1, kDeadline = 2;
    bool claim(int by) noexcept {
        int expected = kOpen;
        return state_.compare_exchange_strong(expected, by, std::memory_order_acq_rel);
    }
    std::atomic<int> state_{kOpen};
};

}  // namespace nclink::detail
