#include "core/worker_pool.hpp"
#include "core/thread_name.hpp"

#include <algorithm>

namespace nclink::core_detail {

namespace {
// A replacement thread that found nothing to do for this long leaves.
constexpr auto kSurplusIdle = std::chrono::seconds(5);
}  // namespace

WorkerPool::WorkerPool(std::size_t size, std::chrono::milliseconds stuck_after, std::string name, std::size_t max_threads) {
    state_->size = std::max<std::size_t>(1, size);
    state_->stuck_after = stuck_after;
    state_->name = std::move(name);
    state_->max_threads = std::max(max_threads, state_->size);
    std::lock_guard<std::mutex> lock(state_->mutex);
    for (std::size_t i = 0; i < state_->size; ++i) start_worker_locked(state_);
}

WorkerPool::~WorkerPool() { stop(); }

void WorkerPool::start_worker_locked(const std::shared_ptr<State>& state) {
    state->workers.emplace_back();
    ++state->live;
    Worker* w = &state->workers.back();
    w->thread = std::thread([state, w] { work(state, w); });
}

void WorkerPool::reap_locked(State& state) {
    for (auto it = state.workers.begin(); it != state.workers.end();) {
        if (it->exited) {
            if (it->thread.joinable()) it->thread.join();  // it has left work(): returns at once
            it = state.workers.erase(it);
        } else {
            ++it;
        }
    }
}

bool WorkerPool::post(std::function<void()> task) {
    State& s = *state_;
    {
        std::lock_guard<std::mutex> lock(s.mutex);
        if (s.stopping) return false;
        s.tasks.push_back(std::move(task));
        reap_locked(s);
        if (s.idle == 0 && s.live < s.max_threads) {
            const auto now = std::chrono::steady_clock::now();
            std::size_t stuck = 0;
            for (const auto& w : s.workers)
                if (w.busy && now - w.busy_since > s.stuck_after) ++stuck;
            if (stuck > 0 && s.live - stuck < s.size) {
                ++s.replacements;
                start_worker_locked(state_);
            }
        }
    }
    s.wake.notify_one();
    return true;
}

void WorkerPool::stop(std::chrono::milliseconds grace) {
    State& s = *state_;
    std::unique_lock<std::mutex> lock(s.mutex);
    s.stopping = true;
    s.wake.notify_all();
    // Everything queued runs first; then every worker leaves, except one
    // stuck in a task.
    s.exited.wait_for(lock, grace,
                      [&] { return std::all_of(s.workers.begin(), s.workers.end(), [](const Worker& w) { return w.exited; }); });
    for (auto& w : s.workers) {
        if (!w.thread.joinable()) continue;
        if (w.exited && w.thread.get_id() != std::this_thread::get_id()) w.thread.join();
        else w.thread.detach();
    }
    s.workers.remove_if([](const Worker& w) { return w.exited; });
}

std::size_t WorkerPool::size() const { return state_->size; }

std::size_t WorkerPool::threads() const {
    std::lock_guard<std::mutex> lock(state_->mutex);
    return state_->live;
}

std::uint64_t WorkerPool::replacements() const {
    std::lock_guard<std::mutex> lock(state_->mutex);
    return state_->replacements;
}

void WorkerPool::work(const std::shared_ptr<State>& state, Worker* self) {
    State& s = *state;
    name_this_thread(s.name);
    std::unique_lock<std::mutex> lock(s.mutex);
    for (;;) {
        ++s.idle;
        bool surplus = false;
        while (!s.stopping && s.tasks.empty()) {
            // A replacement for a stuck thread leaves when it has been idle a while.
            if (s.live > s.size) {
                if (s.wake.wait_for(lock, kSurplusIdle) == std::cv_status::timeout && s.tasks.empty() && s.live > s.size) {
                    surplus = true;
                    break;
                }
            } else {
                s.wake.wait(lock);
            }
        }
        --s.idle;
        if (surplus || (s.tasks.empty() && s.stopping)) break;
        auto task = std::move(s.tasks.front());
        s.tasks.pop_front();
        self->busy = true;
        self->busy_since = std::chrono::steady_clock::now();
        lock.unlock();
        try {
            task();
        } catch (...) {
            // Callers report errors as values; this only keeps the worker alive.
        }
        task = nullptr;  // what the task held goes now, not at the next one
        lock.lock();
        self->busy = false;
    }
    self->exited = true;
    --s.live;
    s.exited.notify_all();
}

}  // namespace nclink::core_detail
