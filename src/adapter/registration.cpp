#include "adapter/registration.hpp"

#include <algorithm>

namespace nclink::adapter_detail {

void Registration::sent(std::string msg_id, Clock::Steady now) {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_ = true;
    retry_armed_ = false;  // a reconnect re-sent it
    msg_id_ = std::move(msg_id);
    deadline_ = now + timeout_;
}

Registration::Answer Registration::answered(const RegisterResponse& response) {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool ours = response.msg_id && response.msg_id->is_string() && response.msg_id->get<std::string>() == msg_id_;
    if (!ours && response.msg_id) return Answer::ignored;  // an answer to an older request
    pending_ = false;
    retry_armed_ = false;
    backoff_ = std::chrono::milliseconds(0);
    registered_ = response.status.ok;
    return registered_ ? Answer::accepted : Answer::refused;
}

Registration::Tick Registration::tick(Clock::Steady now, bool connected) {
    std::lock_guard<std::mutex> lock(mutex_);
    Tick tick;
    if (pending_ && now >= deadline_) {
        tick.first_give_up = backoff_.count() == 0;
        backoff_ = std::min(retry_max_, backoff_.count() == 0 ? timeout_ : backoff_ * 2);
        // A quarter either side keeps the mean wait, so the spread costs no
        // extra requests; never above retry_max (backoff_ is at most that, so
        // high >= low).
        const auto low = backoff_ - backoff_ / 4;
        const auto high = std::min(retry_max_, backoff_ + backoff_ / 4);
        const auto drawn = std::uniform_int_distribution<std::int64_t>(low.count(), high.count())(random_);
        tick.gave_up = std::max(std::chrono::milliseconds(1), std::chrono::milliseconds(drawn));
        pending_ = false;
        retry_armed_ = true;
        retry_at_ = now + tick.gave_up;
    }
    if (retry_armed_ && now >= retry_at_) {
        retry_armed_ = false;
        tick.resend = connected;  // while the link is down, the next connect registers anyway
    }
    return tick;
}

bool Registration::registered() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return registered_;
}

}  // namespace nclink::adapter_detail
