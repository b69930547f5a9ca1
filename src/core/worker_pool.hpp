// Worker threads that several owners share for calls that may block (gateway
// mode: every machine's driver calls, docs/gateway.md "Threads"). FIFO like
// Executor, with one difference that matters for drivers: a call stuck far
// past its deadline must not take a thread the other machines need. When a
// task is posted, no worker is idle and some worker has been inside one task
// for longer than `stuck_after`, the pool starts one more thread, so `size`
// workers that are not stuck are always there (up to `max_threads` in all).
// Threads above `size` leave once idle for a few seconds.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace nclink::core_detail {

class WorkerPool {
public:
    using Time = std::chrono::steady_clock::time_point;

    WorkerPool(std::size_t size, std::chrono::milliseconds stuck_after, std::string name, std::size_t max_threads = 256);
    ~WorkerPool();  ///< stop()s
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// Thread-safe. False after stop(). A task must not throw (a throw is
    /// swallowed so the worker lives on).
    bool post(std::function<void()> task);
    /// Runs what is queued and joins the workers; a worker still inside a
    /// task after `grace` is detached (it owns what it touches when it
    /// comes back). Idempotent.
    void stop(std::chrono::milliseconds grace = std::chrono::milliseconds(2000));

    std::size_t size() const;
    /// Threads now (the size plus replacements of stuck ones).
    std::size_t threads() const;
    /// Threads started to replace stuck ones, over the pool's life.
    std::uint64_t replacements() const;

private:
    struct Worker {
        std::thread thread;
        bool busy = false;
        Time busy_since{};
        bool exited = false;
    };
    // Shared with the workers, so one detached in a stuck task never
    // touches a destroyed pool.
    struct State {
        std::size_t size = 1;
        std::chrono::milliseconds stuck_after{};
        std::string name;
        std::size_t max_threads = 1;
        std::mutex mutex;
        std::condition_variable wake;
        std::condition_variable exited;
        std::deque<std::function<void()>> tasks;
        std::list<Worker> workers;  // stable addresses
        std::size_t idle = 0;
        std::size_t live = 0;  // workers that have not left work()
        std::uint64_t replacements = 0;
        bool stopping = false;
    };
    static void work(const std::shared_ptr<State>& state, Worker* self);
    static void start_worker_locked(const std::shared_ptr<State>& state);
    static void reap_locked(State& state);  // joins workers that left

    std::shared_ptr<State> state_ = std::make_shared<State>();
};

}  // namespace nclink::core_detail
