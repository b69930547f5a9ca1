// A pool of worker threads running posted tasks in FIFO order. Used for
// request handling so transport callback threads never block.
//
// `resident` workers live as long as the pool; up to `threads` in all. A
// worker beyond the resident ones starts when a task is posted and every live
// worker is busy, and ends after `linger` without a task: a terminal's second
// request worker exists during a burst only (docs/footprint.md, "Where the
// threads go").
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace nclink::core_detail {

class Executor {
public:
    /// `threads` workers, all resident (0 is taken as 1).
    explicit Executor(std::size_t threads);
    /// Up to `threads` workers, `resident` of them always (at least 1).
    Executor(std::size_t threads, std::size_t resident, std::chrono::milliseconds linger);
    ~Executor();
    Executor(const Executor&) = delete;
    Executor& operator=(const Executor&) = delete;

    /// Thread-safe. False after stop(). Tasks must not throw (they are wrapped:
    /// an escaping exception is swallowed so a worker never dies).
    bool post(std::function<void()> task);
    /// Runs what is queued, then joins the workers. Idempotent.
    void stop();
    std::size_t queued() const;
    /// Workers alive now, and of them those waiting for a task. Thread-safe.
    std::size_t live() const;
    std::size_t idle() const;

private:
    void work(bool resident);
    void start_worker_locked(bool resident);
    void reap_locked();

    const std::size_t max_threads_;
    const std::chrono::milliseconds linger_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> tasks_;
    bool stopping_ = false;
    std::size_t live_ = 0;  // workers started and not ended
    std::size_t idle_ = 0;  // of them, waiting for a task
    std::vector<std::thread> threads_;
    std::vector<std::thread::id> ended_;  // extra workers gone idle, to join
};

}  // namespace nclink::core_detail
