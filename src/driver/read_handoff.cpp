#include "driver/read_handoff.hpp"

#include <algorithm>
#include <thread>

namespace nclink::driver_detail {
namespace {
constexpr auto kSpin = std::chrono::microseconds(50);
}  // namespace

bool ReadHandoff::run(const Step& step) {
    auto job = std::make_shared<Job>();
    job->step = &step;
    std::unique_lock<std::mutex> lock(mutex_);
    if (!serving_) return false;
    queue_.push_back(job);
    arrived_.notify_one();
    const auto give_up = std::chrono::steady_clock::now() + patience_;
    {
        // The serving thread usually answers within microseconds of being
        // woken: a short spin spares this worker a wake-up of its own.
        lock.unlock();
        const auto spin_end = std::chrono::steady_clock::now() + kSpin;
        while (!job->complete.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < spin_end)
            std::this_thread::yield();
        lock.lock();
    }
    for (;;) {
        if (job->stage == Stage::done) return true;
        if (job->stage == Stage::queued && (!serving_ || std::chrono::steady_clock::now() >= give_up)) {
            // Not running now, so the serving thread cannot touch it again
            // once it is out of the queue.
            queue_.erase(std::find(queue_.begin(), queue_.end(), job));
            job->stage = Stage::withdrawn;
            return false;
        }
        if (job->stage == Stage::running) changed_.wait(lock);
        else changed_.wait_until(lock, give_up);
    }
}

void ReadHandoff::open(std::chrono::nanoseconds patience) {
    std::lock_guard<std::mutex> lock(mutex_);
    serving_ = true;
    patience_ = patience;
}

void ReadHandoff::close() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        serving_ = false;
    }
    changed_.notify_all();  // their workers withdraw them
    arrived_.notify_all();  // a wait_for_work() ends
}

bool ReadHandoff::serving() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return serving_;
}

bool ReadHandoff::has_work() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return !queue_.empty();
}

std::size_t ReadHandoff::serve(Time until) {
    std::size_t steps = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    while (!queue_.empty() && std::chrono::steady_clock::now() < until) {
        const std::shared_ptr<Job> job = queue_.front();
        queue_.pop_front();
        job->stage = Stage::running;
        lock.unlock();
        bool complete = false;
        do {
            complete = (*job->step)();
            ++steps;
        } while (!complete && std::chrono::steady_clock::now() < until);
        lock.lock();
        if (complete) {
            job->stage = Stage::done;
            job->complete.store(true, std::memory_order_release);
        } else {
            job->stage = Stage::queued;  // the rest in the next gap, or by its worker
            queue_.push_front(job);
        }
        changed_.notify_all();
    }
    steps_served_ += steps;
    return steps;
}

bool ReadHandoff::wait_for_work(Time until) {
    std::unique_lock<std::mutex> lock(mutex_);
    return arrived_.wait_until(lock, until, [this] { return !queue_.empty() || !serving_; }) && serving_;
}

std::uint64_t ReadHandoff::steps_served() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return steps_served_;
}

}  // namespace nclink::driver_detail
