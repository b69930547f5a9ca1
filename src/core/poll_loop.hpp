// One thread serving many timed pollers: each poller does the work that is
// due and returns when it next has work. The loop keeps the pollers in a heap
// by deadline and calls only those that are due, so a thousand pollers with
// nothing to do cost nothing. Used where many adapters in one process share
// threads (docs/gateway.md): the sampling scheduler, the uploaders and the
// adapters' housekeeping each become a poller instead of a thread per adapter.
//
// Time is std::chrono::steady_clock (the SystemClock's): pollers driven by a
// ManualClock do not belong on a loop.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <queue>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

namespace nclink::detail {

class PollLoop {
public:
    using Time = std::chrono::steady_clock::time_point;
    /// Runs what is due now; returns the time it next has work
    /// (Time::max() = only when poked). Called on the loop thread only, never
    /// twice at once.
    using Poller = std::function<Time()>;

    PollLoop();
    ~PollLoop();  ///< stop()s
    PollLoop(const PollLoop&) = delete;
    PollLoop& operator=(const PollLoop&) = delete;

    /// Adds a poller, first called at once. Thread-safe. Returns its id (0
    /// after stop()).
    std::uint64_t add(Poller poller);
    /// Calls the poller soon, whatever its deadline (its work changed).
    /// Thread-safe, cheap; unknown ids are ignored.
    void poke(std::uint64_t id);
    /// After return the poller is not running and never runs again (when
    /// called from the poller itself: never again after it returns).
    /// Thread-safe.
    void remove(std::uint64_t id);
    /// Joins the thread; pollers still added are dropped uncalled. Idempotent.
    void stop();

    std::size_t size() const;
    /// Poller calls so far (for statistics and tests).
    std::uint64_t calls() const;

private:
    struct Entry {
        std::shared_ptr<Poller> poller;
        Time deadline = Time::max();
        std::uint64_t generation = 0;  // heap items of older generations are stale
        bool running = false;
        bool poked = false;  // poked while running: call again at once
    };
    struct Due {
        Time at;
        std::uint64_t id;
        std::uint64_t generation;
        bool operator>(const Due& other) const { return at > other.at; }
    };

    void run();
    void schedule_locked(std::uint64_t id, Entry& entry, Time at);

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable idle_;  // a poller finished running (remove() waits for it)
    std::unordered_map<std::uint64_t, Entry> entries_;
    std::priority_queue<Due, std::vector<Due>, std::greater<Due>> heap_;
    Time sleeping_until_ = Time::max();
    std::uint64_t next_id_ = 1;
    std::uint64_t calls_ = 0;
    bool stopping_ = false;
    std::thread thread_;
};

/// Several loops; each poller added goes to the next loop in turn (or the
/// one given), so the work spreads over the threads.
class PollPool {
public:
    explicit PollPool(std::size_t threads);
    PollPool(const PollPool&) = delete;
    PollPool& operator=(const PollPool&) = delete;

    /// The loop the next poller should go to. Thread-safe.
    PollLoop& next();
    std::size_t size() const { return loops_.size(); }
    PollLoop& loop(std::size_t i) { return *loops_[i]; }
    void stop();

private:
    std::vector<std::unique_ptr<PollLoop>> loops_;
    std::mutex mutex_;
    std::size_t turn_ = 0;
};

}  // namespace nclink::detail
