// PeriodicThread (periodic_thread.hpp).
#include "core/periodic_thread.hpp"

#include "core/thread_name.hpp"

namespace nclink::core_detail {

bool PeriodicThread::start(std::chrono::milliseconds period, std::function<void()> task, std::string name) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (thread_.joinable()) return false;
    stopping_ = false;
    thread_ = std::thread([this, period, task = std::move(task), name = std::move(name)] { run(period, task, name); });
    return true;
}

void PeriodicThread::run(std::chrono::milliseconds period, const std::function<void()>& task, const std::string& name) {
    name_this_thread(name);
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        lock.unlock();
        task();
        lock.lock();
        wake_.wait_for(lock, period, [this] { return stopping_; });
    }
}

void PeriodicThread::stop() {
    std::thread joining;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
        joining = std::move(thread_);
    }
    wake_.notify_all();
    if (joining.joinable()) joining.join();
}

bool PeriodicThread::running() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return thread_.joinable() && !stopping_;
}

}  // namespace nclink::core_detail
