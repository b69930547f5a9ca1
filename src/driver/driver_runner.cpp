#include "driver/driver_runner.hpp"
#include "core/thread_name.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <iterator>
#include <optional>

namespace nclink::driver_detail {
namespace {

// Takes `lock` within `wait`. libstdc++ waits on the steady clock with
// pthread_rwlock_clock*lock, which gcc 12's ThreadSanitizer does not
// intercept: it would not see the lock held and report races between calls
// that `calls` keeps apart. Under TSan the wall-clock variant is used (it
// calls pthread_rwlock_timed*lock, which TSan knows); elsewhere the steady
// clock, which a clock step cannot stretch.
template <typename Lock>
bool lock_within(Lock& lock, std::chrono::nanoseconds wait) {
#if defined(__SANITIZE_THREAD__)
    return lock.try_lock_until(std::chrono::system_clock::now() +
                               std::chrono::duration_cast<std::chrono::system_clock::duration>(wait));
#else
    return lock.try_lock_for(wait);
#endif
}

// The queue whose worker this thread is (null elsewhere): a read made from a
// task already running on the driver's worker calls the driver directly
// instead of queueing behind itself.
thread_local const void* tls_worker_of = nullptr;
// The exclusive hold on `calls` of the task running on this worker (a
// serialized driver), so an in-place read can let sampling in between chunks.
thread_local std::unique_lock<CallLock>* tls_exclusive_call = nullptr;
// Whether the task running on this worker holds `calls` (shared or
// exclusive); false in a post_unlocked() task.
thread_local bool tls_holds_calls = false;

// Points read per driver call by an in-place (request) read before sampling
// may cut in: a 10,000-item Query must not hold the driver for its whole read.
constexpr std::size_t kReadChunk = 64;

// The state one waiting caller shares with its task. The task may finish
// after the caller gave up; the shared_ptr keeps the state alive for it.
template <class T>
struct Pending {
    std::mutex mutex;
    std::condition_variable done_cv;
    std::atomic<bool> done{false};
    T value;

    void finish(T result) {
        std::lock_guard<std::mutex> lock(mutex);
        value = std::move(result);
        done.store(true, std::memory_order_release);
        done_cv.notify_all();
    }

    /// Most driver calls take microseconds: spin that long before sleeping,
    /// which saves a thread wake-up (~25 us on the reference VM) per call.
    /// Bounded, so a slow driver costs at most kSpin of CPU.
    bool wait(std::chrono::milliseconds timeout) {
        static constexpr auto kSpin = std::chrono::microseconds(50);
        const auto spin_end = std::chrono::steady_clock::now() + kSpin;
        while (std::chrono::steady_clock::now() < spin_end) {
            if (done.load(std::memory_order_acquire)) return true;
            std::this_thread::yield();
        }
        std::unique_lock<std::mutex> lock(mutex);
        return done_cv.wait_for(lock, timeout, [&] { return done.load(std::memory_order_acquire); });
    }
};

void call_read(Driver& driver, const std::vector<PointRef>& points, std::vector<Result<Json>>& results) {
    try {
        driver.read(points, results);
    } catch (const std::exception& e) {
        // A throwing driver must not take the adapter down.
        for (auto& r : results) r = make_error(ErrorCode::unavailable, std::string("driver threw: ") + e.what());
    }
}

// The machine link, asked before every call: a throw counts as unknown.
MachineLinkStatus ask_link(const Driver& driver) {
    try {
        return driver.link();
    } catch (...) {
        return {};
    }
}

std::optional<Error> disconnected(const Driver& driver) {
    const MachineLinkStatus link = ask_link(driver);
    if (link.state != MachineLink::disconnected) return std::nullopt;
    return make_error(ErrorCode::unavailable,
                      link.reason.empty() ? std::string("machine disconnected") : "machine disconnected: " + link.reason);
}

Error not_served_error(const std::string& id) { return make_error(ErrorCode::unavailable, "the driver does not serve " + id); }

// What the driver gets for points prepared against `generation`: the points
// themselves (identity) when they are current, else a copy re-resolved
// against the current table without the points it does not serve; slots[k]
// is the caller's index of points[k]. Current points are passed as they are,
// without a scan per read: every caller leaves not_served points out when it
// plans (request handlers, sample lanes, event polls).
struct CallPlan {
    bool identity = true;
    std::vector<PointRef> points;
    std::vector<std::size_t> slots;
};

void plan_call(const std::vector<PointRef>& in, std::uint64_t generation, const PointTable* table, CallPlan& plan) {
    const bool stale = table != nullptr && generation != table->generation();
    if (!stale) {
        plan.identity = true;
        return;
    }
    plan.identity = false;
    plan.points.clear();
    plan.slots.clear();
    for (std::size_t i = 0; i < in.size(); ++i) {
        PointHandle handle = in[i].handle;
        if (stale) {
            const PointRef* now = table->find(in[i].id);
            handle = now ? now->handle : not_served;  // gone from the model: the driver never saw it bound
        }
        if (handle == not_served) continue;
        plan.points.push_back(PointRef{in[i].id, in[i].kind, handle});
        plan.slots.push_back(i);
    }
}

}  // namespace

void DriverRunner::read_locked(Driver& driver, const Queue& queue, const std::vector<PointRef>& points, std::uint64_t generation,
                               std::vector<Result<Json>>& results) {
    results.assign(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    if (queue.closed.load(std::memory_order_acquire)) {
        for (auto& r : results) r = make_error(ErrorCode::unavailable, "driver stopped");
        return;
    }
    if (auto down = disconnected(driver)) {
        for (auto& r : results) r = *down;
        return;
    }
    CallPlan plan;
    plan_call(points, generation, queue.table.get(), plan);
    if (plan.identity) {
        call_read(driver, points, results);
        return;
    }
    for (std::size_t i = 0; i < points.size(); ++i) results[i] = not_served_error(points[i].id);
    if (plan.points.empty()) return;
    std::vector<Result<Json>> some(plan.points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    call_read(driver, plan.points, some);
    for (std::size_t k = 0; k < plan.slots.size() && k < some.size(); ++k) results[plan.slots[k]] = std::move(some[k]);
}

Result<void> DriverRunner::write_locked(Driver& driver, const Queue& queue, const WriteRequest& request, std::uint64_t generation) {
    if (queue.closed.load(std::memory_order_acquire)) return make_error(ErrorCode::unavailable, "driver stopped");
    if (auto down = disconnected(driver)) return *down;
    const PointTable* table = queue.table.get();
    const WriteRequest* call = &request;
    WriteRequest resolved;
    if (table != nullptr && generation != table->generation()) {
        const PointRef* now = table->find(request.id);
        if (!now || now->handle == not_served) return not_served_error(request.id);
        resolved = request;
        resolved.handle = now->handle;
        call = &resolved;
    } else if (request.handle == not_served) {
        return not_served_error(request.id);
    }
    try {
        return driver.write(*call);
    } catch (const std::exception& e) {
        return make_error(ErrorCode::unavailable, std::string("driver threw: ") + e.what());
    }
}

DriverRunner::DriverRunner(std::shared_ptr<Driver> driver, Options options, Logger logger)
    : driver_(std::move(driver)), options_(options), logger_(std::move(logger)), name_(driver_->info().name) {
    const std::size_t count = driver_->info().concurrent ? std::max<std::size_t>(1, options_.concurrent_workers) : 1;
    queue_->concurrent = driver_->info().concurrent;
    if (!queue_->concurrent) queue_->calls.serialize();
    if (options_.pool) {
        queue_->pool = options_.pool;
        queue_->max_drains = count;
        return;
    }
    queue_->running_workers = count;
    for (std::size_t i = 0; i < count; ++i) workers_.emplace_back([queue = queue_] { work(queue); });
}

DriverRunner::~DriverRunner() { stop(); }

void DriverRunner::run_task(Queue& queue, Queue::Task& task) {
    if (!task.hold_calls) {
        task.run();
    } else if (queue.concurrent) {
        std::shared_lock<CallLock> call(queue.calls);
        tls_holds_calls = true;
        task.run();
        tls_holds_calls = false;
    } else {
        yield_to_priority(queue);
        std::unique_lock<CallLock> call(queue.calls);
        tls_exclusive_call = &call;
        tls_holds_calls = true;
        task.run();
        tls_holds_calls = false;
        tls_exclusive_call = nullptr;
    }
    task.run = nullptr;  // what it captured goes before the next one
}

void DriverRunner::work(const std::shared_ptr<Queue>& queue) {
    core_detail::name_this_thread("nclink-driver");
    tls_worker_of = queue.get();
    std::unique_lock<std::mutex> lock(queue->mutex);
    for (;;) {
        queue->wake.wait(lock, [&] { return queue->stopping || !queue->tasks.empty(); });
        if (queue->tasks.empty() && queue->stopping) break;
        auto task = std::move(queue->tasks.front());
        queue->tasks.pop_front();
        lock.unlock();
        run_task(*queue, task);
        lock.lock();
    }
    --queue->running_workers;
    queue->exited.notify_all();
}

void DriverRunner::drain(const std::shared_ptr<Queue>& queue) {
    // Tasks of one driver per turn before the drain goes to the back of the
    // pool's queue: other machines' calls wait at most this many of its calls.
    constexpr int kTurn = 8;
    const void* const previous = tls_worker_of;
    tls_worker_of = queue.get();
    std::unique_lock<std::mutex> lock(queue->mutex);
    for (int served = 0; !queue->tasks.empty(); ++served) {
        if (served == kTurn) {
            lock.unlock();
            if (queue->pool->post([queue] { drain(queue); })) {
                tls_worker_of = previous;
                return;  // still counted in running_workers: the re-posted drain goes on
            }
            lock.lock();  // the pool is stopping: finish here
            served = 0;
            if (queue->tasks.empty()) break;
        }
        auto task = std::move(queue->tasks.front());
        queue->tasks.pop_front();
        lock.unlock();
        run_task(*queue, task);
        lock.lock();
    }
    // Still under the lock that saw the queue empty: a post() after this
    // sees no drain running and starts one.
    --queue->running_workers;
    queue->exited.notify_all();
    tls_worker_of = previous;
}

void DriverRunner::yield_to_priority(const Queue& queue) {
    // Bounded: a sampler that keeps the driver busy cannot stop requests.
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(5);
    while (queue.priority_waiters.load(std::memory_order_acquire) > 0 && std::chrono::steady_clock::now() < until)
        std::this_thread::yield();
}

void DriverRunner::count_timeout() {
    std::lock_guard<std::mutex> lock(queue_->mutex);
    ++queue_->timeouts;
}

bool DriverRunner::post(std::function<void(Driver&)> task) {
    return enqueue(Queue::Task{[driver = driver_, task = std::move(task)] { task(*driver); }, true});
}

bool DriverRunner::post_unlocked(std::function<void()> task) { return enqueue(Queue::Task{std::move(task), false}); }

bool DriverRunner::enqueue(Queue::Task task) {
    bool start_drain = false;
    {
        std::lock_guard<std::mutex> lock(queue_->mutex);
        if (queue_->stopping) return false;
        queue_->tasks.push_back(std::move(task));
        if (queue_->pool && queue_->running_workers < queue_->max_drains) {
            ++queue_->running_workers;
            start_drain = true;
        }
    }
    if (!queue_->pool) {
        queue_->wake.notify_one();
        return true;
    }
    if (start_drain && !queue_->pool->post([queue = queue_] { drain(queue); })) {
        std::lock_guard<std::mutex> lock(queue_->mutex);
        queue_->tasks.pop_back();
        --queue_->running_workers;
        queue_->exited.notify_all();
        return false;
    }
    return true;
}

std::vector<Result<Json>> DriverRunner::read(const std::vector<PointRef>& points, std::uint64_t generation) {
    return read(points, options_.call_timeout, generation);
}

template <typename Call>
void DriverRunner::call_in_place(Queue& queue, Call&& call) {
    if (tls_holds_calls) {
        call();
    } else if (queue.concurrent) {
        std::shared_lock<CallLock> hold(queue.calls);
        call();
    } else {
        yield_to_priority(queue);
        std::unique_lock<CallLock> hold(queue.calls);
        call();
    }
}

std::vector<Result<Json>> DriverRunner::read(const std::vector<PointRef>& points, std::chrono::milliseconds timeout,
                                             std::uint64_t generation) {
    using Results = std::vector<Result<Json>>;
    if (tls_worker_of == queue_.get()) {
        // On the driver's own worker (a driver-affine request): call in place.
        // `this` is not touched after the call, so an abandoned worker that
        // returns late from a stuck driver finds nothing destroyed under it.
        const std::shared_ptr<Driver> driver = driver_;
        const std::shared_ptr<Queue> queue = queue_;
        Results results;
        // A post_unlocked() task takes the driver per chunk (and lets a
        // waiting sampler in before each: a 1,000-item Query must not keep a
        // 1 ms channel from its reads). A task holding it exclusively lets
        // the sampler in between chunks.
        const bool per_chunk_lock = !tls_holds_calls;
        std::unique_lock<CallLock>* hold = tls_exclusive_call;
        if (!per_chunk_lock && (hold == nullptr || points.size() <= kReadChunk)) {
            read_locked(*driver, *queue, points, generation, results);
            return results;
        }
        // Each chunk goes through read_locked() under the (re-)taken lock, so
        // a bind() that got in between re-resolves the rest against its table;
        // it answers for every one of its points, in order, appended here.
        results.reserve(points.size());
        std::vector<PointRef> chunk;
        Results chunk_results;
        std::size_t at = 0;
        const ReadHandoff::Step step = [&] {  // one chunk, under the lock its runner holds
            const std::size_t end = std::min(points.size(), at + kReadChunk);
            chunk.assign(points.begin() + static_cast<std::ptrdiff_t>(at), points.begin() + static_cast<std::ptrdiff_t>(end));
            read_locked(*driver, *queue, chunk, generation, chunk_results);
            std::move(chunk_results.begin(), chunk_results.end(), std::back_inserter(results));
            at = end;
            return at >= points.size();
        };
        if (per_chunk_lock) {
            // With a fast channel the sampling thread runs the read between
            // its ticks (read_handoff.hpp); what it did not start in time is
            // read here, a chunk per lock.
            if (points.empty() || queue->handoff.run(step)) return results;
            while (at < points.size()) call_in_place(*queue, step);
            return results;
        }
        while (at < points.size()) {
            step();
            if (at < points.size() && queue->priority_waiters.load(std::memory_order_acquire) > 0) {
                hold->unlock();
                yield_to_priority(*queue);
                hold->lock();
            }
        }
        return results;
    }
    auto pending = std::make_shared<Pending<Results>>();
    const bool queued = post([pending, points, generation, queue = queue_](Driver& driver) {
        Results results;
        read_locked(driver, *queue, points, generation, results);
        pending->finish(std::move(results));
    });
    if (!queued) return Results(points.size(), Result<Json>(make_error(ErrorCode::unavailable, "driver stopped")));
    if (!pending->wait(timeout)) {
        count_timeout();
        logger_.warn("driver '{}': read of {} point(s) did not finish within {} ms", name_, points.size(), timeout.count());
        return Results(
            points.size(),
            Result<Json>(make_error(ErrorCode::timeout, fmt::format("driver did not answer within {} ms", timeout.count()))));
    }
    std::lock_guard<std::mutex> lock(pending->mutex);
    return std::move(pending->value);
}

void DriverRunner::start_serving_reads(std::chrono::nanoseconds patience) {
    if (!queue_->concurrent) queue_->handoff.open(patience);
}

void DriverRunner::stop_serving_reads() { queue_->handoff.close(); }

void DriverRunner::serve_reads(std::chrono::steady_clock::time_point until) {
    ReadHandoff& handoff = queue_->handoff;
    while (handoff.has_work() || handoff.wait_for_work(until)) {
        const auto now = std::chrono::steady_clock::now();
        if (now >= until) return;
        std::unique_lock<CallLock> hold(queue_->calls, std::defer_lock);
        if (!lock_within(hold, until - now)) return;  // a write or bind holds it: the workers' patience covers this
        handoff.serve(until);
    }
}

std::uint64_t DriverRunner::reads_served() const { return queue_->handoff.steps_served(); }

std::uint64_t DriverRunner::sampling_waits() const { return queue_->sampling_waits.load(std::memory_order_relaxed); }

namespace {

// Runs `call` under `Lock` (shared for a concurrent driver, exclusive for a
// serialized one) if the lock is had within `wait`. A wait of a quarter of
// `wait` or more, or in vain, is counted in `waited`.
template <typename Lock, typename Call>
bool call_locked(CallLock& calls, std::chrono::nanoseconds wait, Call& call, std::atomic<std::uint64_t>& waited) {
    Lock lock(calls, std::defer_lock);
    if (!lock.try_lock()) {
        const auto start = std::chrono::steady_clock::now();
        const bool had = lock_within(lock, wait);
        if (!had || std::chrono::steady_clock::now() - start >= wait / 4) waited.fetch_add(1, std::memory_order_relaxed);
        if (!had) return false;
    }
    call();
    return true;
}

}  // namespace

template <typename Call>
bool DriverRunner::call_direct(std::chrono::nanoseconds wait, Call&& call) {
    queue_->priority_waiters.fetch_add(1, std::memory_order_acq_rel);
    struct Done {
        std::atomic<int>& waiters;
        ~Done() { waiters.fetch_sub(1, std::memory_order_acq_rel); }
    } done{queue_->priority_waiters};
    const bool called = queue_->concurrent
                            ? call_locked<std::shared_lock<CallLock>>(queue_->calls, wait, call, queue_->sampling_waits)
                            : call_locked<std::unique_lock<CallLock>>(queue_->calls, wait, call, queue_->sampling_waits);
    if (!called) count_timeout();
    return called;
}

void DriverRunner::read_direct(const std::vector<PointRef>& points, std::vector<Result<Json>>& results,
                               std::chrono::nanoseconds wait, std::uint64_t generation) {
    const bool called = call_direct(wait, [&] { read_locked(*driver_, *queue_, points, generation, results); });
    if (!called) results.assign(points.size(), Result<Json>(make_error(ErrorCode::timeout, "driver busy with another call")));
}

DriverRunner::TypedRead DriverRunner::read_samples_direct(const std::vector<PointRef>& points, SampleValue* out,
                                                          std::chrono::nanoseconds wait, std::uint64_t generation) {
    // Every slot null before the driver writes: one it skips must not keep
    // the ring's previous sample. A null is all-zero bytes (kind null = 0,
    // payload 0, size 0; test_protocol checks it), so this is a memset, whose
    // whole-line stores spare the ring's cold lines a read before the write
    // (a slot is rewritten only once per ring's worth of rows).
    std::memset(static_cast<void*>(out), 0, points.size() * sizeof(SampleValue));
    bool supported = true;
    const auto typed_read = [&](const std::vector<PointRef>& some, SampleValue* into) {
        try {
            supported = driver_->read_samples(some, into);
        } catch (...) {
            std::fill(into, into + some.size(), SampleValue::null());  // a half-written row is not trusted
        }
    };
    const bool called = call_direct(wait, [&] {
        if (queue_->closed.load(std::memory_order_acquire)) return;
        if (disconnected(*driver_)) return;  // the row stays null
        CallPlan plan;
        plan_call(points, generation, queue_->table.get(), plan);
        if (plan.identity) {
            typed_read(points, out);
            return;
        }
        if (plan.points.empty()) return;
        std::vector<SampleValue> some(plan.points.size());
        typed_read(plan.points, some.data());
        if (!supported) return;
        for (std::size_t k = 0; k < plan.slots.size(); ++k) out[plan.slots[k]] = some[k];
    });
    if (!called) return TypedRead::busy;
    return supported ? TypedRead::done : TypedRead::unsupported;
}

Result<std::shared_ptr<const PointTable>> DriverRunner::bind(const std::vector<BindPoint>& points) {
    // Exclusive whatever info().concurrent says: no read may straddle two
    // bindings.
    std::unique_lock<CallLock> calls(queue_->calls, std::defer_lock);
    if (!lock_within(calls, options_.call_timeout)) {
        count_timeout();
        return make_error(ErrorCode::timeout,
                          fmt::format("driver busy: bind() could not start within {} ms", options_.call_timeout.count()));
    }
    if (queue_->closed.load(std::memory_order_acquire)) return make_error(ErrorCode::unavailable, "driver stopped");
    std::vector<PointHandle> handles(points.size(), no_handle);
    Result<void> bound = ok_result();
    try {
        bound = driver_->bind(points, handles);
    } catch (const std::exception& e) {
        bound = make_error(ErrorCode::unavailable, std::string("driver threw in bind(): ") + e.what());
    }
    if (!bound) return std::move(bound).error();
    handles.resize(points.size(), no_handle);  // a driver that shrank the vector
    std::vector<PointRef> refs;
    refs.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) refs.push_back(PointRef{points[i].id, points[i].kind, handles[i]});
    std::lock_guard<std::mutex> table_lock(queue_->table_mutex);
    auto table = std::make_shared<const PointTable>(++queue_->generations, std::move(refs));
    queue_->table = table;
    return table;
}

PointRef DriverRunner::current_ref(const std::string& id) const {
    std::lock_guard<std::mutex> lock(queue_->table_mutex);
    if (queue_->table)
        if (const PointRef* ref = queue_->table->find(id)) return *ref;
    return PointRef{id, DataKind::single, no_handle};
}

MachineLinkStatus DriverRunner::link() const { return ask_link(*driver_); }

Result<void> DriverRunner::write(const WriteRequest& request, std::uint64_t generation) {
    if (tls_worker_of == queue_.get()) {
        // On the driver's own worker (a driver-affine Set): call in place,
        // under the driver's lock unless the task already holds it.
        const std::shared_ptr<Driver> driver = driver_;
        const std::shared_ptr<Queue> queue = queue_;
        Result<void> written = make_error(ErrorCode::unavailable);
        call_in_place(*queue, [&] { written = write_locked(*driver, *queue, request, generation); });
        return written;
    }
    struct Outcome {
        Result<void> result = make_error(ErrorCode::unavailable);
    };
    // Who moves first: the task taking the write to the driver, or the
    // caller giving up at its deadline. A write must not reach the machine
    // after the application was told 203.
    enum : int { kQueued = 0, kStarted = 1, kWithdrawn = 2 };
    auto stage = std::make_shared<std::atomic<int>>(kQueued);
    auto pending = std::make_shared<Pending<Outcome>>();
    const bool queued = post([pending, stage, request, generation, queue = queue_](Driver& driver) {
        int expected = kQueued;
        if (!stage->compare_exchange_strong(expected, kStarted, std::memory_order_acq_rel)) return;
        Outcome outcome;
        outcome.result = write_locked(driver, *queue, request, generation);
        pending->finish(std::move(outcome));
    });
    if (!queued) return make_error(ErrorCode::unavailable, "driver stopped");
    if (!pending->wait(options_.call_timeout)) {
        count_timeout();
        int expected = kQueued;
        if (stage->compare_exchange_strong(expected, kWithdrawn, std::memory_order_acq_rel)) {
            logger_.warn("driver '{}': write of {} withdrawn: the driver was busy for {} ms", name_, request.id,
                         options_.call_timeout.count());
            return make_error(ErrorCode::timeout, fmt::format("driver busy for {} ms: not written", options_.call_timeout.count()));
        }
        logger_.warn("driver '{}': write of {} did not finish within {} ms", name_, request.id, options_.call_timeout.count());
        return make_error(
            ErrorCode::timeout,
            fmt::format("driver did not finish the write within {} ms: it may still take effect", options_.call_timeout.count()));
    }
    std::lock_guard<std::mutex> lock(pending->mutex);
    return std::move(pending->value.result);
}

void DriverRunner::stop(std::chrono::milliseconds grace) {
    std::unique_lock<std::mutex> lock(queue_->mutex);
    if (queue_->stopping && workers_.empty()) return;
    queue_->stopping = true;
    queue_->wake.notify_all();
    const bool all_exited = queue_->exited.wait_for(lock, grace, [this] { return queue_->running_workers == 0; });
    lock.unlock();
    for (auto& worker : workers_) {
        if (all_exited) worker.join();
        else worker.detach();  // stuck in the driver: cannot be joined
    }
    workers_.clear();
    if (!all_exited) {
        // Nothing queued may start once its owner is gone: a worker that
        // returns late from the stuck call finds the queue empty and exits.
        {
            std::lock_guard<std::mutex> queue_lock(queue_->mutex);
            queue_->tasks.clear();
        }
        logger_.error("driver '{}' did not return within {} ms of shutdown; its worker thread is abandoned", name_, grace.count());
        return;
    }
    {
        // No read_direct() may be inside the driver when it closes.
        std::unique_lock<CallLock> calls(queue_->calls, std::defer_lock);
        if (!lock_within(calls, grace)) {
            logger_.error("driver '{}': a direct read did not return within {} ms of shutdown; not closing it", name_,
                          grace.count());
            return;
        }
        queue_->closed.store(true, std::memory_order_release);
    }
    try {
        driver_->close();
    } catch (const std::exception& e) {
        logger_.error("driver '{}': close() threw: {}", name_, e.what());
    }
}

std::uint64_t DriverRunner::timeouts() const {
    std::lock_guard<std::mutex> lock(queue_->mutex);
    return queue_->timeouts;
}

}  // namespace nclink::driver_detail
