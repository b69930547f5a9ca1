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
//
// It waits on a thread of its own ("nclink-deadline"), or, given a PollHost,
// as one pollable of that host: a single adapter runs it on its background
// threads (docs/footprint.md, "Where the threads go"), where the callbacks,
// which only hand an answer to a request worker, are as quick as a poll
// must be.
#pragma once

#include "core/poll_host.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <queue>
#include <thread>
#include <vector>

namespace nclink::core_detail {

class DeadlineWatchdog {
public:
    using Time = std::chrono::steady_clock::time_point;

    /// `host`: null for a thread of its own, else a pollable of that host
    /// (which must outlive the watchdog).
    explicit DeadlineWatchdog(PollHost* host = nullptr);
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
    /// Runs what is due; the time of the next entry (host mode).
    Time poll();

    PollHost* host_ = nullptr;
    PollHost::Handle entry_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> entries_;
    Time sleeping_until_ = Time::max();
    bool stopping_ = false;
    std::thread thread_;
};

/// The one answer to a request, claimed either by the worker that did the
/// work or by the watchdog when the deadline passed first. Exactly one wins.
/// A worker about to do what must not happen after a timeout answer (a
/// write) first marks the work started: a deadline that comes before that
/// mark owns the request (the work is then never done), one that comes after
/// it still answers, knowing the work may take effect.
class AnswerClaim {
public:
    enum class Deadline { lost, before_start, during_work };

    /// The worker, before work that must not follow a timeout answer: true
    /// when the deadline has not claimed the request (do the work), false
    /// when it has (drop the request untouched).
    bool start_for_worker() noexcept { return move(kOpen, kStarted); }
    /// The worker: true when it may answer (the deadline has not claimed it).
    bool claim_for_worker() noexcept { return move(kOpen, kWorker) || move(kStarted, kWorker); }
    /// The watchdog: true when the worker has not answered yet.
    bool claim_for_deadline() noexcept { return claim_deadline() != Deadline::lost; }
    /// The watchdog, telling apart a request the worker never started from
    /// one it is still working on.
    Deadline claim_deadline() noexcept {
        if (move(kOpen, kDeadline)) return Deadline::before_start;
        if (move(kStarted, kDeadline)) return Deadline::during_work;
        return Deadline::lost;
    }

private:
    static constexpr int kOpen = 0, kStarted = 1, kWorker = 2, kDeadline = 3;
    bool move(int from, int to) noexcept { return state_.compare_exchange_strong(from, to, std::memory_order_acq_rel); }
    std::atomic<int> state_{kOpen};
};

}  // namespace nclink::core_detail
