#include "core/deadline_watchdog.hpp"
#include "core/thread_name.hpp"

namespace nclink::core_detail {

DeadlineWatchdog::DeadlineWatchdog(PollHost* host) : host_(host) {
    if (host_) entry_ = host_->add([this](PollHost::Time) { return poll(); });
    else thread_ = std::thread([this] { loop(); });
}

DeadlineWatchdog::~DeadlineWatchdog() { stop(); }

bool DeadlineWatchdog::arm(Time at, std::function<void()> on_expiry) {
    bool wake = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_) return false;
        entries_.push(Entry{at, std::move(on_expiry)});
        wake = at < sleeping_until_;
    }
    if (!wake) return true;
    if (host_) host_->wake(entry_);
    else wake_.notify_one();
    return true;
}

void DeadlineWatchdog::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_ && !thread_.joinable() && !entry_) return;
        stopping_ = true;
    }
    if (host_ && entry_) {
        host_->remove(entry_);  // returns when no poll of it runs
        entry_.reset();
    }
    wake_.notify_one();
    if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    entries_ = {};
}

DeadlineWatchdog::Time DeadlineWatchdog::poll() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_ && !entries_.empty() && entries_.top().at <= std::chrono::steady_clock::now()) {
        auto run = std::move(const_cast<Entry&>(entries_.top()).run);
        entries_.pop();
        lock.unlock();
        run();
        lock.lock();
    }
    // arm() wakes the pollable only for an entry earlier than this.
    sleeping_until_ = stopping_ || entries_.empty() ? Time::max() : entries_.top().at;
    return sleeping_until_;
}

void DeadlineWatchdog::loop() {
    name_this_thread("nclink-deadline");
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        const auto now = std::chrono::steady_clock::now();
        if (!entries_.empty() && entries_.top().at <= now) {
            auto run = std::move(const_cast<Entry&>(entries_.top()).run);
            entries_.pop();
            lock.unlock();
            run();
            lock.lock();
            continue;
        }
        sleeping_until_ = entries_.empty() ? Time::max() : entries_.top().at;
        if (sleeping_until_ == Time::max()) wake_.wait(lock);
        else wake_.wait_until(lock, sleeping_until_);
        sleeping_until_ = Time::max();
    }
}

}  // namespace nclink::core_detail
