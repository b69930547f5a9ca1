#include "http/worker_pool.hpp"

namespace nclink::http {

namespace {
// Set while a pool thread's job runs and that thread was lent to a stream.
thread_local bool lent_thread = false;
thread_local bool pool_thread = false;
}  // namespace

WorkerPool::WorkerPool(std::size_t workers) : workers_(workers == 0 ? 1 : workers) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t i = 0; i < workers_; ++i) spawn_locked();
}

WorkerPool::~WorkerPool() { shutdown(); }

void WorkerPool::spawn_locked() {
    // Threads that ended (lent ones whose stream is over) are joined here, so
    // a server that runs for months does not collect finished thread objects.
    for (auto it = threads_.begin(); it != threads_.end();) {
        if (it->done) {
            if (it->thread.joinable()) it->thread.join();
            it = threads_.erase(it);
        } else {
            ++it;
        }
    }
    threads_.emplace_back();
    auto self = std::prev(threads_.end());
    self->thread = std::thread([this, self] { run(self); });
}

bool WorkerPool::submit(std::function<void()> job) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (shutdown_) return false;
        jobs_.push_back(std::move(job));
    }
    wake_.notify_one();
    return true;
}

void WorkerPool::lend_current() {
    if (!pool_thread || lent_thread) return;
    std::lock_guard<std::mutex> lock(mutex_);
    lent_thread = true;
    ++lent_;
    if (!shutdown_) spawn_locked();
}

void WorkerPool::run(std::list<Thread>::iterator self) {
    pool_thread = true;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return shutdown_ || !jobs_.empty(); });
        if (jobs_.empty()) break;  // shut down, nothing left to run
        auto job = std::move(jobs_.front());
        jobs_.pop_front();
        lock.unlock();
        try {
            job();
        } catch (...) {
            // a job never takes a worker down with it
        }
        lock.lock();
        if (lent_thread) {  // its place went to a new thread when it was lent
            --lent_;
            break;
        }
    }
    self->done = true;
}

void WorkerPool::shutdown() {
    std::list<Thread> threads;
    {
        std::unique_lock<std::mutex> lock(mutex_);
        shutdown_ = true;
        wake_.notify_all();
    }
    // Threads are only added while not shut down, so the list is final once
    // every thread it holds is done; join outside the lock.
    for (;;) {
        std::list<Thread> batch;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            batch.splice(batch.end(), threads_);
        }
        if (batch.empty()) break;
        for (auto& t : batch)
            if (t.thread.joinable() && t.thread.get_id() != std::this_thread::get_id()) t.thread.join();
        threads.splice(threads.end(), batch);
    }
}

std::size_t WorkerPool::threads() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t alive = 0;
    for (const auto& t : threads_) alive += t.done ? 0 : 1;
    return alive;
}

}  // namespace nclink::http
