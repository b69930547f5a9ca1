#include "core/executor.hpp"
#include "core/thread_name.hpp"

#include <algorithm>

namespace nclink::core_detail {

Executor::Executor(std::size_t threads) : Executor(threads, threads, std::chrono::milliseconds(0)) {}

Executor::Executor(std::size_t threads, std::size_t resident, std::chrono::milliseconds linger)
    : max_threads_(std::max<std::size_t>(threads, 1)), linger_(linger) {
    resident = std::clamp<std::size_t>(resident, 1, max_threads_);
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t i = 0; i < resident; ++i) start_worker_locked(true);
}

Executor::~Executor() { stop(); }

void Executor::start_worker_locked(bool resident) {
    ++live_;
    threads_.emplace_back([this, resident] { work(resident); });
}

void Executor::reap_locked() {
    // An ended worker has left work() under the lock it gave up last: joining
    // it here waits at most for its thread to finish exiting.
    for (const auto id : ended_) {
        auto found = std::find_if(threads_.begin(), threads_.end(), [&](const std::thread& t) { return t.get_id() == id; });
        if (found == threads_.end()) continue;
        found->join();
        threads_.erase(found);
    }
    ended_.clear();
}

bool Executor::post(std::function<void()> task) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_) return false;
        tasks_.push_back(std::move(task));
        // More queued than waiting workers: another worker, while the pool
        // has room.
        if (tasks_.size() > idle_ && live_ < max_threads_) {
            reap_locked();
            start_worker_locked(false);
        }
    }
    wake_.notify_one();
    return true;
}

void Executor::stop() {
    std::vector<std::thread> threads;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
        threads.swap(threads_);
        ended_.clear();
    }
    wake_.notify_all();
    for (auto& t : threads)
        if (t.joinable()) {
            if (t.get_id() == std::this_thread::get_id()) t.detach();  // stop() from a task: the worker ends by itself
            else t.join();
        }
}

std::size_t Executor::queued() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return tasks_.size();
}

std::size_t Executor::live() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_;
}

std::size_t Executor::idle() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return idle_;
}

void Executor::work(bool resident) {
    name_this_thread("nclink-request");
    std::unique_lock<std::mutex> lock(mutex_);
    const auto ready = [this] { return stopping_ || !tasks_.empty(); };
    for (;;) {
        ++idle_;
        const bool woken = resident ? (wake_.wait(lock, ready), true) : wake_.wait_for(lock, linger_, ready);
        --idle_;
        if (!woken || tasks_.empty()) {  // an extra worker idle for `linger`, or stopping and drained
            --live_;
            if (!woken && !stopping_) ended_.push_back(std::this_thread::get_id());
            return;
        }
        auto task = std::move(tasks_.front());
        tasks_.pop_front();
        lock.unlock();
        try {
            task();
        } catch (...) {
            // Handlers report errors as values; this only keeps the worker alive.
        }
        lock.lock();
    }
}

}  // namespace nclink::core_detail
