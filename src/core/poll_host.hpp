// A few threads that serve many pieces of periodic work ("pollables") at the
// deadlines the work itself names. Gateway mode (docs/gateway.md, "Threads")
// puts every machine's sampling scheduler, uploader and housekeeping on one
// host, so a process with N machines runs a fixed number of such threads
// instead of several per machine, and an idle machine costs no wake-ups
// between its deadlines.
//
// Contract:
// - add() schedules the first poll at once; a poll returns the steady time
//   of its next one (time_point::max(): only when woken).
// - One pollable never runs on two threads at once; different pollables run
//   in parallel on different threads. One free thread waits for the next
//   deadline and serves what is due in deadline order; a pollable that is
//   due while that thread is still in a poll waits for it, at most
//   kBackstop, then another thread takes it (so a burst of due work is
//   served by one thread while it keeps up, and a stuck poll holds the
//   others back by kBackstop, not for as long as it is stuck). A pollable
//   added or woken ahead of everything due goes to a free thread at once.
// - wake() makes a pollable due now (also while it runs: it runs again right
//   after). Thread-safe, cheap, never blocks on a running poll.
// - remove() returns once the pollable is not running and never will again
//   (called from inside its own poll, it returns at once and the poll is not
//   run again). Thread-safe.
// - A poll must not throw (a throw is swallowed and it is polled again in
//   one second, so one broken pollable cannot stop the host).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <queue>
#include <string>
#include <thread>
#include <vector>

namespace nclink::core_detail {

class PollHost {
public:
    using Time = std::chrono::steady_clock::time_point;
    using Poll = std::function<Time(Time now)>;
    struct Entry;
    using Handle = std::shared_ptr<Entry>;

    /// `threads` (at least 1) serving threads; `name` shows in `top -H`;
    /// `backstop`: see kBackstop (tests that must not depend on the box's
    /// scheduling give a long one).
    PollHost(std::size_t threads, std::string name, std::chrono::milliseconds backstop = kBackstop);
    ~PollHost();  ///< stop()s
    PollHost(const PollHost&) = delete;
    PollHost& operator=(const PollHost&) = delete;

    Handle add(Poll poll);
    void wake(const Handle& handle);
    void remove(const Handle& handle);
    /// Joins the threads; pollables still added are not polled again. Idempotent.
    void stop();

    std::size_t threads() const { return threads_.size(); }
    /// Pollables added and not removed.
    std::size_t size() const;
    /// Polls run so far (for benchmarks).
    std::uint64_t polls() const;
    /// How often a serving thread woke from waiting (tests: few futile wake-ups).
    std::uint64_t wakeups() const;

    /// How long past a deadline the threads not watching it wait before they
    /// take it over from a watcher still busy in a poll: the most a stuck or
    /// slow poll delays the others.
    static constexpr std::chrono::milliseconds kBackstop{5};
    std::chrono::milliseconds backstop() const { return backstop_; }

private:
    struct Due {
        Time at;
        std::uint64_t generation;
        Handle entry;
        bool operator>(const Due& other) const { return at > other.at; }
    };
    void work(std::size_t index);
    void schedule_locked(const Handle& entry, Time at);
    /// Whether a serving thread waits for a deadline at or before `at`.
    bool watched_locked(Time at) const;

    mutable std::mutex mutex_;
    std::condition_variable wake_;      // serving threads: earlier work, or stop
    std::condition_variable finished_;  // remove(): a poll finished
    std::priority_queue<Due, std::vector<Due>, std::greater<Due>> due_;
    std::size_t entries_ = 0;
    std::uint64_t polls_ = 0;
    std::uint64_t wakeups_ = 0;
    std::vector<Time> watching_;  // per serving thread: the deadline it waits for (max: none)
    bool stopping_ = false;
    const std::string name_;
    const std::chrono::milliseconds backstop_;
    std::vector<std::thread> threads_;
};

}  // namespace nclink::core_detail
