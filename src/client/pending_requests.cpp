#include "client/pending_requests.hpp"

namespace nclink::client_detail {

bool PendingRequests::add(PendingRequest request) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return false;
    by_deadline_.emplace(request.deadline, request.id);
    std::string id = request.id;
    by_id_.insert_or_assign(std::move(id), std::move(request));
    return true;
}

std::shared_ptr<Responder> PendingRequests::peek(const std::string& id, TopicKind* response_kind) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_id_.find(id);
    if (it == by_id_.end()) return nullptr;
    if (response_kind) *response_kind = it->second.response_kind;
    return it->second.responder;
}

std::optional<PendingRequest> PendingRequests::take(const std::string& id) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_id_.find(id);
    if (it == by_id_.end()) return std::nullopt;
    PendingRequest request = std::move(it->second);
    by_id_.erase(it);
    auto [first, last] = by_deadline_.equal_range(request.deadline);
    for (auto d = first; d != last; ++d)
        if (d->second == id) {
            by_deadline_.erase(d);
            break;
        }
    return request;
}

std::vector<PendingRequest> PendingRequests::take_expired(Clock::time_point now) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<PendingRequest> expired;
    while (!by_deadline_.empty() && by_deadline_.begin()->first <= now) {
        const std::string id = by_deadline_.begin()->second;
        by_deadline_.erase(by_deadline_.begin());
        const auto it = by_id_.find(id);
        if (it == by_id_.end()) continue;
        expired.push_back(std::move(it->second));
        by_id_.erase(it);
        if (timed_out_.insert(id).second) timed_out_order_.push_back(id);
        if (timed_out_order_.size() > remembered_timeouts) {
            timed_out_.erase(timed_out_order_.front());
            timed_out_order_.pop_front();
        }
    }
    return expired;
}

std::vector<PendingRequest> PendingRequests::close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    std::vector<PendingRequest> all;
    all.reserve(by_id_.size());
    for (auto& [id, request] : by_id_) all.push_back(std::move(request));
    by_id_.clear();
    by_deadline_.clear();
    return all;
}

bool PendingRequests::timed_out_recently(const std::string& id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return timed_out_.count(id) > 0;
}

std::optional<Clock::time_point> PendingRequests::next_deadline() const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (by_deadline_.empty()) return std::nullopt;
    return by_deadline_.begin()->first;
}

std::size_t PendingRequests::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return by_id_.size();
}

}  // namespace nclink::client_detail
