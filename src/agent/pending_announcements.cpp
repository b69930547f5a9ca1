#include "agent/pending_announcements.hpp"

#include <algorithm>

namespace nclink::agent_detail {

void PendingAnnouncements::hold(const std::string& tid, Clock::Steady now, std::chrono::milliseconds grace) {
    const auto at = now + grace;
    if (!due_.emplace(tid, at).second) return;
    // A clock that went back (a test's) must not put an entry before
    // earlier ones: the queue stays in order of due time.
    queue_.emplace_back(queue_.empty() ? at : std::max(at, queue_.back().first), tid);
}

std::vector<std::string> PendingAnnouncements::take_due(Clock::Steady now) {
    std::vector<std::string> out;
    while (!queue_.empty() && queue_.front().first <= now) {
        auto [at, tid] = std::move(queue_.front());
        queue_.pop_front();
        const auto it = due_.find(tid);
        if (it == due_.end() || it->second > now) continue;  // cancelled, or held again later
        due_.erase(it);
        out.push_back(std::move(tid));
    }
    return out;
}

}  // namespace nclink::agent_detail
