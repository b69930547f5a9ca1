// A thread that runs one task every period until stopped: the housekeeping
// loops of the long-lived services (timeouts, liveness, state files). stop()
// wakes the thread at once instead of waiting out the period, and joins it.
// The task runs on that thread only, never twice at once. start() and stop()
// may be called from any thread but the task's own; stop() is idempotent and
// runs from the destructor.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace nclink::core_detail {

class PeriodicThread {
public:
    PeriodicThread() = default;
    PeriodicThread(const PeriodicThread&) = delete;
    PeriodicThread& operator=(const PeriodicThread&) = delete;
    ~PeriodicThread() { stop(); }

    /// Runs `task` at once, then every `period` (measured from the end of the
    /// previous run). The thread is named `name` (top -H, debuggers). A second
    /// start() while running is ignored (returns false).
    bool start(std::chrono::milliseconds period, std::function<void()> task, std::string name);
    void stop();
    bool running() const;

private:
    void run(std::chrono::milliseconds period, const std::function<void()>& task, const std::string& name);

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
    std::thread thread_;
};

}  // namespace nclink::core_detail
