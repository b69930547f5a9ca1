#include "client/dispatcher.hpp"

#include <exception>
#include <utility>

namespace nclink::client_detail {

Dispatcher::Dispatcher(Hooks hooks) : hooks_(std::move(hooks)) {}

Dispatcher::~Dispatcher() { stop(); }

void Dispatcher::start() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (thread_.joinable() || stopping_) return;
    accepting_ = true;
    thread_ = std::thread([this] { run(); });
    thread_id_ = thread_.get_id();
}

bool Dispatcher::post(Task task) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!accepting_) return false;
        tasks_.push_back(std::move(task));
    }
    wake_.notify_one();
    return true;
}

void Dispatcher::poke() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        poked_ = true;
    }
    wake_.notify_one();
}

void Dispatcher::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (on_dispatch_thread()) return;  // would join itself
        accepting_ = false;
        stopping_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
}

bool Dispatcher::on_dispatch_thread() const noexcept { return std::this_thread::get_id() == thread_id_; }

bool Dispatcher::running() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return accepting_;
}

// Callbacks are user code: an exception must not take the thread down.
template <class F>
void Dispatcher::guarded(F&& f) noexcept {
    try {
        f();
    } catch (const std::exception& e) {
        if (hooks_.on_exception) hooks_.on_exception(e.what());
    } catch (...) {
        if (hooks_.on_exception) hooks_.on_exception("unknown exception");
    }
}

void Dispatcher::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        const auto ready = [this] { return stopping_ || poked_ || !tasks_.empty(); };
        lock.unlock();
        const auto deadline = hooks_.next_deadline ? hooks_.next_deadline() : std::nullopt;
        lock.lock();
        if (deadline) wake_.wait_until(lock, *deadline, ready);
        else wake_.wait(lock, ready);
        poked_ = false;
        std::deque<Task> batch;
        batch.swap(tasks_);
        const bool stopping = stopping_;
        lock.unlock();
        for (auto& task : batch) guarded(task);
        if (hooks_.on_wake) guarded([this] { hooks_.on_wake(Clock::now()); });
        if (stopping) {
            // post() refuses since stopping_ was set, so nothing is left behind.
            if (hooks_.on_stop) guarded(hooks_.on_stop);
            return;
        }
        lock.lock();
    }
}

}  // namespace nclink::client_detail
