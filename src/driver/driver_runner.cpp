#include "driver/driver_runner.hpp"

#include <algorithm>
#include <atomic>

namespace nclink::detail {
namespace {

// The queue whose worker this thread is (null elsewhere): a read made from a
// task already running on the driver's worker calls the driver directly
// instead of queueing behind itself.
thread_local const void* tls_worker_of = nullptr;
// The exclusive hold on `calls` of the task running on this worker (a
// serialized driver), so an in-place read can let sampling in between chunks.
thread_local std::unique_lock<std::shared_timed_mutex>* tls_exclusive_call = nullptr;

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

}  // namespace

DriverRunner::DriverRunner(std::shared_ptr<Driver> driver, Options options, Logger logger)
    : driver_(std::move(driver)), options_(options), logger_(std::move(logger)), name_(driver_->info().name) {
    const std::size_t count = driver_->info().concurrent ? std::max<std::size_t>(1, options_.concurrent_workers) : 1;
    queue_->running_workers = count;
    queue_->concurrent = driver_->info().concurrent;
    for (std::size_t i = 0; i < count; ++i) workers_.emplace_back([queue = queue_] { work(queue); });
}

DriverRunner::~DriverRunner() { stop(); }

void DriverRunner::work(const std::shared_ptr<Queue>& queue) {
    tls_worker_of = queue.get();
    std::unique_lock<std::mutex> lock(queue->mutex);
    for (;;) {
        queue->wake.wait(lock, [&] { return queue->stopping || !queue->tasks.empty(); });
        if (queue->tasks.empty() && queue->stopping) break;
        auto task = std::move(queue->tasks.front());
        queue->tasks.pop_front();
        lock.unlock();
        if (queue->concurrent) {
            std::shared_lock<std::shared_timed_mutex> call(queue->calls);
            task();
        } else {
            yield_to_priority(*queue);
            std::unique_lock<std::shared_timed_mutex> call(queue->calls);
            tls_exclusive_call = &call;
            task();
            tls_exclusive_call = nullptr;
        }
        lock.lock();
    }
    --queue->running_workers;
    queue->exited.notify_all();
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
    {
        std::lock_guard<std::mutex> lock(queue_->mutex);
        if (queue_->stopping) return false;
        queue_->tasks.emplace_back([driver = driver_, task = std::move(task)] { task(*driver); });
    }
    queue_->wake.notify_one();
    return true;
}

std::vector<Result<Json>> DriverRunner::read(const std::vector<PointRef>& points) {
    return read(points, options_.call_timeout);
}

std::vector<Result<Json>> DriverRunner::read(const std::vector<PointRef>& points, std::chrono::milliseconds timeout) {
    using Results = std::vector<Result<Json>>;
    if (tls_worker_of == queue_.get()) {
        // On the driver's own worker (a driver-affine request): call in place.
        // `this` is not touched after the call, so an abandoned worker that
        // returns late from a stuck driver finds nothing destroyed under it.
        const std::shared_ptr<Driver> driver = driver_;
        Results results(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
        std::unique_lock<std::shared_timed_mutex>* hold = tls_exclusive_call;
        if (hold == nullptr || points.size() <= kReadChunk) {
            call_read(*driver, points, results);
            return results;
        }
        // In chunks, letting a waiting sampler in between them.
        Queue& queue = *queue_;
        std::vector<PointRef> chunk;
        Results chunk_results;
        for (std::size_t at = 0; at < points.size(); at += kReadChunk) {
            const std::size_t end = std::min(points.size(), at + kReadChunk);
            chunk.assign(points.begin() + static_cast<std::ptrdiff_t>(at), points.begin() + static_cast<std::ptrdiff_t>(end));
            chunk_results.assign(chunk.size(), Result<Json>(make_error(ErrorCode::unavailable)));
            call_read(*driver, chunk, chunk_results);
            std::move(chunk_results.begin(), chunk_results.end(), results.begin() + static_cast<std::ptrdiff_t>(at));
            if (end < points.size() && queue.priority_waiters.load(std::memory_order_acquire) > 0) {
                hold->unlock();
                yield_to_priority(queue);
                hold->lock();
            }
        }
        return results;
    }
    auto pending = std::make_shared<Pending<Results>>();
    const bool queued = post([pending, points](Driver& driver) {
        Results results(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
        call_read(driver, points, results);
        pending->finish(std::move(results));
    });
    if (!queued) return Results(points.size(), Result<Json>(make_error(ErrorCode::unavailable, "driver stopped")));
    if (!pending->wait(timeout)) {
        count_timeout();
        logger_.warn("driver '{}': read of {} point(s) did not finish within {} ms", name_, points.size(), timeout.count());
        return Results(points.size(), Result<Json>(make_error(ErrorCode::timeout,
                                                               fmt::format("driver did not answer within {} ms", timeout.count()))));
    }
    std::lock_guard<std::mutex> lock(pending->mutex);
    return std::move(pending->value);
}

namespace {

// Runs `call` under `Lock` (shared for a concurrent driver, exclusive for a
// serialized one) if the lock is had within `wait`.
template <typename Lock, typename Call>
bool call_locked(std::shared_timed_mutex& calls, std::chrono::nanoseconds wait, Call& call) {
    Lock lock(calls, std::defer_lock);
    if (!lock.try_lock_for(wait)) return false;
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
                            ? call_locked<std::shared_lock<std::shared_timed_mutex>>(queue_->calls, wait, call)
                            : call_locked<std::unique_lock<std::shared_timed_mutex>>(queue_->calls, wait, call);
    if (!called) count_timeout();
    return called;
}

void DriverRunner::read_direct(const std::vector<PointRef>& points, std::vector<Result<Json>>& results,
                               std::chrono::nanoseconds wait) {
    results.assign(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    const bool called = call_direct(wait, [&] {
        if (queue_->closed.load(std::memory_order_acquire)) {
            for (auto& r : results) r = make_error(ErrorCode::unavailable, "driver stopped");
            return;
        }
        try {
            driver_->read(points, results);
        } catch (const std::exception& e) {
            for (auto& r : results) r = make_error(ErrorCode::unavailable, std::string("driver threw: ") + e.what());
        }
    });
    if (!called)
        for (auto& r : results) r = make_error(ErrorCode::timeout, "driver busy with another call");
}

DriverRunner::TypedRead DriverRunner::read_samples_direct(const std::vector<PointRef>& points, SampleValue* out,
                                                          std::chrono::nanoseconds wait) {
    std::fill(out, out + points.size(), SampleValue::null());
    bool supported = true;
    const bool called = call_direct(wait, [&] {
        if (queue_->closed.load(std::memory_order_acquire)) return;
        try {
            supported = driver_->read_samples(points, out);
        } catch (...) {
            std::fill(out, out + points.size(), SampleValue::null());  // a half-written row is not trusted
        }
    });
    if (!called) return TypedRead::busy;
    return supported ? TypedRead::done : TypedRead::unsupported;
}

Result<void> DriverRunner::write(const WriteRequest& request) {
    struct Outcome {
        Result<void> result = make_error(ErrorCode::unavailable);
    };
    auto pending = std::make_shared<Pending<Outcome>>();
    const bool queued = post([pending, request](Driver& driver) {
        Outcome outcome;
        try {
            outcome.result = driver.write(request);
        } catch (const std::exception& e) {
            outcome.result = make_error(ErrorCode::unavailable, std::string("driver threw: ") + e.what());
        }
        pending->finish(std::move(outcome));
    });
    if (!queued) return make_error(ErrorCode::unavailable, "driver stopped");
    if (!pending->wait(options_.call_timeout)) {
        count_timeout();
        logger_.warn("driver '{}': write of {} did not finish within {} ms", name_, request.id, options_.call_timeout.count());
        return make_error(ErrorCode::timeout, fmt::format("driver did not answer within {} ms", options_.call_timeout.count()));
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
        if (all_exited)
            worker.join();
        else
            worker.detach();  // stuck in the driver: cannot be joined
    }
    workers_.clear();
    if (!all_exited) {
        // Nothing queued may start once its owner is gone: a worker that
        // returns late from the stuck call finds the queue empty and exits.
        {
            std::lock_guard<std::mutex> queue_lock(queue_->mutex);
            queue_->tasks.clear();
        }
        logger_.error("driver '{}' did not return within {} ms of shutdown; its worker thread is abandoned", name_,
                      grace.count());
        return;
    }
    {
        // No read_direct() may be inside the driver when it closes.
        std::unique_lock<std::shared_timed_mutex> calls(queue_->calls, std::defer_lock);
        if (!calls.try_lock_for(grace)) {
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

}  // namespace nclink::detail
