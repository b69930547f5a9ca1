#include "methods/method_run.hpp"

#include <algorithm>
#include <cmath>

namespace nclink::methods_detail {

const char* to_string(RunPhase phase) noexcept {
    switch (phase) {
        case RunPhase::waiting: return "waiting";
        case RunPhase::executing: return "executing";
        case RunPhase::stopped: return "stopped";
        case RunPhase::sleep: return "sleep";
    }
    return "?";
}

MethodRun::MethodRun(std::uint64_t serial_number, std::string method, ParsedTopic topic, MessageId id, Json checked_args)
    : serial(serial_number),
      method_id(std::move(method)),
      call_topic(std::move(topic)),
      call_id(std::move(id)),
      args(std::move(checked_args)) {}

void MethodRun::progress(double percent) {
    if (!std::isfinite(percent)) return;  // a driver's NaN never reaches the wire
    std::lock_guard<std::mutex> lock(mutex_);
    state_.progress = std::clamp(percent, 0.0, 100.0);
}

bool MethodRun::cancelled() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_.cancel_requested;
}

bool MethodRun::checkpoint() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (state_.cancel_requested) return false;
    if (!state_.pause_requested) return true;
    state_.phase = RunPhase::stopped;
    lock.unlock();
    changed();
    lock.lock();
    wake_.wait(lock, [&] { return !state_.pause_requested || state_.cancel_requested; });
    const bool go_on = !state_.cancel_requested;
    state_.phase = RunPhase::executing;
    lock.unlock();
    if (go_on) changed();  // a cancelled run's next DTU is its Result
    return go_on;
}

bool MethodRun::begin() {
    bool go = true;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        go = !state_.cancel_requested;
        state_.phase = go ? RunPhase::executing : RunPhase::sleep;
    }
    changed();
    return go;
}

void MethodRun::request_stop() {
    std::lock_guard<std::mutex> lock(mutex_);
    state_.pause_requested = true;
}

void MethodRun::request_resume() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        state_.pause_requested = false;
    }
    wake_.notify_all();
}

void MethodRun::request_cancel() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        state_.cancel_requested = true;
    }
    wake_.notify_all();
}

MethodRun::Snapshot MethodRun::snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
}

void MethodRun::changed() {
    if (listener_) listener_(*this);
}

}  // namespace nclink::methods_detail
