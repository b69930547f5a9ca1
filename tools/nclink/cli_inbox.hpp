// Hands items from the client's dispatch thread to the main thread of a
// streaming subcommand (watch, state), which waits with Ctrl-C checks.
#pragma once

#include "cli_device.hpp"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

namespace nclink::cli {

template <class T>
class Inbox {
public:
    void push(T item) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            items_.push_back(std::move(item));
        }
        ready_.notify_one();
    }
    /// The next item; std::nullopt when `deadline` passes or Ctrl-C is pressed.
    std::optional<T> pop(std::chrono::steady_clock::time_point deadline) {
        std::unique_lock<std::mutex> lock(mutex_);
        while (items_.empty()) {
            if (interrupted() || std::chrono::steady_clock::now() >= deadline) return std::nullopt;
            // Short waits: a signal handler cannot notify a condition variable.
            ready_.wait_for(lock, std::chrono::milliseconds(100));
        }
        T item = std::move(items_.front());
        items_.pop_front();
        return item;
    }

private:
    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<T> items_;
};

}  // namespace nclink::cli
