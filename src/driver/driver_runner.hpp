// Runs calls into one Driver on worker threads the SDK owns, with deadlines.
// One worker (calls serialized) unless the driver declares itself concurrent.
// A caller waits at most the deadline; a call still running then answers
// Timeout (203) and its late result is discarded. A slow driver therefore
// never blocks MQTT keep-alive, other devices, or the caller beyond the
// deadline.
//
// Every call into the driver also gets, inside the serialization lock:
// - the machine link: while Driver::link() says disconnected, reads answer
//   202 "machine disconnected: <reason>" (typed reads null) and writes 202,
//   without a driver call;
// - the binding (driver.hpp, "Handles"): points prepared against an earlier
//   bind() than the current one (or by hand, `unbound`) are re-resolved by
//   id, and those the binding does not serve (or no longer has) answer 202
//   without reaching the driver. Points prepared against the current binding
//   pass untouched (no copy, no lookup); callers leave its not_served points
//   out when they plan.
#pragma once

#include "core/worker_pool.hpp"
#include "driver/call_lock.hpp"
#include "driver/point_table.hpp"
#include "driver/read_handoff.hpp"

#include <nclink/driver.hpp>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <atomic>
#include <thread>
#include <vector>

namespace nclink::driver_detail {

class DriverRunner {
public:
    struct Options {
        std::chrono::milliseconds call_timeout{1000};
        std::size_t concurrent_workers = 2;  ///< used only when the driver is concurrent
        /// Gateway mode (include/nclink/shared_threads.hpp): run the calls on
        /// this shared pool instead of the runner's own worker(s), still one
        /// at a time (or concurrent_workers at a time for a concurrent
        /// driver). Must outlive stop().
        core_detail::WorkerPool* pool = nullptr;
    };

    DriverRunner(std::shared_ptr<Driver> driver, Options options, Logger logger);
    ~DriverRunner();
    DriverRunner(const DriverRunner&) = delete;
    DriverRunner& operator=(const DriverRunner&) = delete;

    /// Calls Driver::bind() for the points of a model being installed, on
    /// the calling thread, exclusively (no other driver call runs meanwhile,
    /// also on a concurrent driver; waits at most call_timeout for running
    /// calls, else 203). On success the new table becomes the current
    /// binding. A driver error (or throw: 202) is returned unchanged.
    /// Thread-safe.
    Result<std::shared_ptr<const PointTable>> bind(const std::vector<BindPoint>& points);
    /// The current binding's ref of `id` (a METHOD, for run_method()), or an
    /// unbound ref {id, single, no_handle} when there is none. Thread-safe.
    PointRef current_ref(const std::string& id) const;

    /// Thread-safe. One result per point, in order. `generation`: the
    /// PointTable the points come from (unbound for hand-made refs). Called
    /// from a task running on this runner's own worker (a driver-affine
    /// task, see post()), the driver is called in place without a deadline:
    /// whoever posted the task watches its deadline (the adapter's Query path
    /// does).
    std::vector<Result<Json>> read(const std::vector<PointRef>& points, std::uint64_t generation = unbound);
    std::vector<Result<Json>> read(const std::vector<PointRef>& points, std::chrono::milliseconds timeout,
                                   std::uint64_t generation = unbound);
    /// Reads on the CALLING thread (no hand-off to a worker: the sampling
    /// path, where a thread wake-up per tick costs more than the read).
    /// Still serialized with the workers' calls on a serialized driver: waits
    /// at most `wait` for a running call to finish, then answers Timeout (203)
    /// for every point. The driver call itself cannot be interrupted, so use
    /// it only where a hanging read may stall the caller. Thread-safe.
    void read_direct(const std::vector<PointRef>& points, std::vector<Result<Json>>& results, std::chrono::nanoseconds wait,
                     std::uint64_t generation = unbound);
    enum class TypedRead { done, unsupported, busy };
    /// The typed form of read_direct() (Driver::read_samples): `out` is set
    /// to nulls first. `unsupported` when the driver does not implement it
    /// (nothing read: use read_direct()); `busy` when a running call did not
    /// finish within `wait` (counted as a timeout; `out` stays null). A throw
    /// leaves `out` null. Text values in `out` borrow the driver's storage
    /// until the next read_samples_direct(). Thread-safe.
    TypedRead read_samples_direct(const std::vector<PointRef>& points, SampleValue* out, std::chrono::nanoseconds wait,
                                  std::uint64_t generation = unbound);
    /// Thread-safe. `request.handle` from the PointTable of `generation`.
    /// A write still queued when the caller's deadline passes is withdrawn:
    /// it never reaches the driver after the caller answered 203 (the 203
    /// then says "not written"). One the driver had already started answers
    /// 203 saying it may still take effect. Called from a task on this
    /// runner's own worker (a driver-affine Set), the driver is called in
    /// place without a deadline, as read() is.
    Result<void> write(const WriteRequest& request, std::uint64_t generation = unbound);
    /// Queues `task` on a worker without waiting (long-running work such as
    /// methods). Thread-safe. False after stop().
    bool post(std::function<void(Driver&)> task);
    /// Like post(), but the task does not hold the driver while it runs: the
    /// calls it makes through this runner (read()) take the driver one by
    /// one (a long read in chunks), so sampling reads get in between them
    /// and while the task does other work (parsing a request, encoding the
    /// answer). The task must reach the driver only through this runner.
    /// Thread-safe. False after stop().
    bool post_unlocked(std::function<void()> task);

    /// Serving the requests' reads on the sampling thread (read_handoff.hpp),
    /// for a serialized driver (no effect on a concurrent one, whose reads do
    /// not exclude each other). From start_serving_reads() on, a request's
    /// read waits (at most `patience` before it reads itself) for the caller
    /// of serve_reads() to run it. Call the three from the sampling thread.
    void start_serving_reads(std::chrono::nanoseconds patience);
    void stop_serving_reads();
    /// Runs handed-over reads until `until`, holding the driver for them,
    /// and waits for more meanwhile (without holding it): the gap between
    /// two sampling ticks.
    void serve_reads(std::chrono::steady_clock::time_point until);
    /// Chunks of requests' reads run by serve_reads() so far. Thread-safe.
    std::uint64_t reads_served() const;
    /// Sampling reads (read_direct(), read_samples_direct()) that waited a
    /// quarter of their wait or more for the driver, or in vain: the sign
    /// that serving the requests' reads would help. Thread-safe.
    std::uint64_t sampling_waits() const;

    /// Stops taking calls, waits up to `grace` for running calls, closes the
    /// driver. A worker stuck in the driver past `grace` is abandoned (and
    /// logged), tasks not yet started are dropped, and the driver is not
    /// closed.
    void stop(std::chrono::milliseconds grace = std::chrono::milliseconds(2000));

    const Driver& driver() const { return *driver_; }
    /// The driver itself, for calls made on threads other than the workers:
    /// methods run on method threads of their own, beside read()/write()
    /// (driver.hpp, threading contract). Shared, so a method thread abandoned
    /// at shutdown never holds a dangling driver.
    std::shared_ptr<Driver> shared_driver() const { return driver_; }
    std::uint64_t timeouts() const;
    /// True when callers waiting for the driver lend their priority to the
    /// call running in it (a serialized driver; call_lock.hpp).
    bool inherits_priority() const noexcept { return queue_->calls.inherits_priority(); }
    /// Driver::link(), a throw taken as unknown. Thread-safe.
    MachineLinkStatus link() const;

private:
    // Owned jointly by the runner and its workers, so a worker abandoned in a
    // stuck driver call never touches a destroyed runner.
    struct Queue {
        std::mutex mutex;
        std::condition_variable wake;
        std::condition_variable exited;
        struct Task {
            std::function<void()> run;
            bool hold_calls = true;  // false: post_unlocked(), it takes the driver per call
        };
        std::deque<Task> tasks;
        bool stopping = false;
        std::size_t running_workers = 0;  // own workers alive; on a pool: drains posted or running
        core_detail::WorkerPool* pool = nullptr;
        std::size_t max_drains = 1;  // on a pool: drains at once
        // Serializes driver calls between the workers and read_direct():
        // exclusive per call for a serialized driver, shared for a concurrent
        // one; stop() takes it exclusively before close(). Priority
        // inheriting for a serialized driver (call_lock.hpp).
        CallLock calls;
        bool concurrent = false;
        std::atomic<bool> closed{false};
        // Sampling deadlines come first: callers of read_direct() /
        // read_samples_direct() waiting for `calls` now. A worker lets them
        // in before its next task, and between the chunks of an in-place
        // read (a flood of requests must not starve sampling).
        std::atomic<int> priority_waiters{0};
        // Requests' reads handed to the sampling thread (serialized driver
        // with a fast channel).
        ReadHandoff handoff;
        std::atomic<std::uint64_t> sampling_waits{0};
        std::uint64_t timeouts = 0;
        // The current binding: written under `calls` held exclusively (and
        // table_mutex), read by driver calls under `calls` (and by
        // current_ref() under table_mutex).
        std::shared_ptr<const PointTable> table;
        mutable std::mutex table_mutex;
        std::uint64_t generations = 0;
    };
    static void work(const std::shared_ptr<Queue>& queue);
    /// On a pool: runs the queue's tasks until it is empty (re-posting
    /// itself now and then, so one busy driver shares the pool's threads).
    static void drain(const std::shared_ptr<Queue>& queue);
    /// One task under the calls lock (shared for a concurrent driver).
    static void run_task(Queue& queue, Queue::Task& task);
    bool enqueue(Queue::Task task);
    // The bodies of the calls, run under the calls lock (see the top).
    static void read_locked(Driver& driver, const Queue& queue, const std::vector<PointRef>& points, std::uint64_t generation,
                            std::vector<Result<Json>>& results);
    static Result<void> write_locked(Driver& driver, const Queue& queue, const WriteRequest& request, std::uint64_t generation);
    /// Waits (bounded) while a sampling read waits for `calls`.
    static void yield_to_priority(const Queue& queue);
    /// From a task on this runner's own worker: runs `call` in place, taking
    /// `calls` for it (after a waiting sampler) unless the task holds it.
    template <typename Call>
    static void call_in_place(Queue& queue, Call&& call);
    /// Runs `call` on the calling thread, serialized with the workers' calls;
    /// false (and a counted timeout) when the lock was not had within `wait`.
    template <typename Call>
    bool call_direct(std::chrono::nanoseconds wait, Call&& call);
    void count_timeout();

    std::shared_ptr<Driver> driver_;
    const Options options_;
    const Logger logger_;
    const std::string name_;
    std::shared_ptr<Queue> queue_ = std::make_shared<Queue>();
    std::vector<std::thread> workers_;
};

}  // namespace nclink::driver_detail
