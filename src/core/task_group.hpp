// One owner's share of an Executor that several owners use (gateway mode:
// every machine's request handling on one pool, docs/gateway.md "Threads").
// The owner posts through its group; close() stops taking tasks and waits for
// the ones it posted that are queued or running, so the owner can be
// destroyed while the pool serves on for the others.
#pragma once

#include "core/executor.hpp"

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>

namespace nclink::core_detail {

class TaskGroup {
public:
    explicit TaskGroup(std::shared_ptr<Executor> executor) : executor_(std::move(executor)), state_(std::make_shared<State>()) {}
    ~TaskGroup() { close(); }
    TaskGroup(const TaskGroup&) = delete;
    TaskGroup& operator=(const TaskGroup&) = delete;

    /// Thread-safe. False after close() (or when the executor stopped).
    bool post(std::function<void()> task) {
        {
            std::lock_guard<std::mutex> lock(state_->mutex);
            if (state_->closed) return false;
            ++state_->outstanding;
        }
        auto done = [state = state_] {
            std::lock_guard<std::mutex> lock(state->mutex);
            if (--state->outstanding == 0) state->idle.notify_all();
        };
        const bool posted = executor_->post([task = std::move(task), done]() mutable {
            try {
                task();
            } catch (...) {
                // As Executor: a handler's escaping exception never kills a worker.
            }
            done();
        });
        if (!posted) done();
        return posted;
    }

    /// Takes no more tasks and waits until every task posted so far ran.
    /// Idempotent. Not from one of this group's tasks.
    void close() {
        std::unique_lock<std::mutex> lock(state_->mutex);
        state_->closed = true;
        state_->idle.wait(lock, [&] { return state_->outstanding == 0; });
    }

    std::size_t outstanding() const {
        std::lock_guard<std::mutex> lock(state_->mutex);
        return state_->outstanding;
    }

private:
    // Shared with the posted tasks: the last one may finish after close()
    // returned only if it never decremented, which cannot happen; shared
    // anyway so the notify never touches a destroyed group.
    struct State {
        std::mutex mutex;
        std::condition_variable idle;
        std::size_t outstanding = 0;
        bool closed = false;
    };
    std::shared_ptr<Executor> executor_;
    std::shared_ptr<State> state_;
};

}  // namespace nclink::core_detail
