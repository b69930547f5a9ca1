// A fixed pool of worker threads running posted tasks in FIFO order. Used for
// request handling so transport callback threads never block.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace nclink::core_detail {

class Executor {
public:
    explicit Executor(std::size_t threads);
    ~Executor();
    Executor(const Executor&) = delete;
    Executor& operator=(const Executor&) = delete;

    /// Thread-safe. False after stop(). Tasks must not throw (they are wrapped:
    /// an escaping exception is swallowed so a worker never dies).
    bool post(std::function<void()> task);
    /// Runs what is queued, then joins the workers. Idempotent.
    void stop();
    std::size_t queued() const;

private:
    void work();

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> tasks_;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace nclink::core_detail
