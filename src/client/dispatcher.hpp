// The client's dispatch thread: runs posted tasks one at a time in order and
// wakes at the next request deadline. Every user callback runs here, so the
// transport's callback thread only copies a message and posts it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace nclink::client_detail {

class Dispatcher {
public:
    using Clock = std::chrono::steady_clock;
    using Task = std::function<void()>;

    struct Hooks {
        std::function<std::optional<Clock::time_point>()> next_deadline;  ///< when to wake at the latest
        std::function<void(Clock::time_point now)> on_wake;               ///< after each batch of tasks / wake-up
        std::function<void()> on_stop;                                    ///< last act on the thread, after the remaining tasks
        std::function<void(const char* what)> on_exception;               ///< a task threw (a user callback); it is dropped
    };

    explicit Dispatcher(Hooks hooks);
    ~Dispatcher();  ///< stop()s
    Dispatcher(const Dispatcher&) = delete;
    Dispatcher& operator=(const Dispatcher&) = delete;

    void start();
    /// Queues a task; false when not running (the caller runs it itself).
    bool post(Task task);
    /// Recomputes the wake-up time (a nearer deadline was added).
    void poke();
    /// Runs the queued tasks and on_stop, then joins. Not from the thread itself.
    void stop();
    bool on_dispatch_thread() const noexcept;
    bool running() const;

private:
    void run();
    template <class F>
    void guarded(F&& f) noexcept;

    Hooks hooks_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<Task> tasks_;
    bool accepting_ = false;
    bool stopping_ = false;
    bool poked_ = false;
    std::thread thread_;
    std::atomic<std::thread::id> thread_id_{};
};

}  // namespace nclink::client_detail
