// The HTTP server's worker threads: `workers` of them always take requests,
// and a worker that begins a long-lived stream (SSE) hands its place to a new
// thread for as long as the stream lasts (lend_current()), so streams never
// count against the request workers (docs/bridge.md "Slow and idle clients").
//
// Threading: submit() and shutdown() from any thread; lend_current() only
// from a job running on one of the pool's threads. shutdown() runs the jobs
// still queued (each must return promptly once its owner stops) and joins
// every thread; afterwards submit() runs nothing.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <list>
#include <mutex>
#include <thread>

namespace nclink::http {

class WorkerPool {
public:
    explicit WorkerPool(std::size_t workers);
    ~WorkerPool();  ///< shutdown()s
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// Queues `job`; false after shutdown() (the job is not run).
    bool submit(std::function<void()> job);
    /// The calling pool thread leaves the request workers until its current
    /// job returns (then the thread ends); a new worker takes its place.
    void lend_current();
    void shutdown();

    /// Threads now: request workers plus lent ones.
    std::size_t threads() const;

private:
    struct Thread {
        std::thread thread;
        bool done = false;
    };
    void spawn_locked();
    void run(std::list<Thread>::iterator self);

    const std::size_t workers_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> jobs_;
    std::list<Thread> threads_;
    std::size_t lent_ = 0;
    bool shutdown_ = false;
};

}  // namespace nclink::http
