// The client's broker link (client_link.hpp).
#include "client/client_link.hpp"

namespace nclink::client_detail {

LinkState ClientLink::state() const {
    std::lock_guard<std::mutex> lock(state_mutex_);
    return state_;
}

bool ClientLink::wait_connected(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(state_mutex_);
    return state_changed_.wait_for(lock, timeout, [&] { return state_ == LinkState::connected; });
}

void ClientLink::note(LinkState state) {
    {
        std::lock_guard<std::mutex> lock(state_mutex_);
        state_ = state;
    }
    state_changed_.notify_all();
}

Result<SubscriptionId> ClientLink::subscribe(std::vector<std::string> filters, AnyHandler handler) {
    std::lock_guard<std::mutex> lock(subscribe_mutex_);
    auto sub = subscriptions_.add(filters, std::move(handler));
    if (auto r = transport_->subscribe(std::move(filters), 1); !r) {
        bool found = false;
        (void)subscriptions_.remove(sub->id, found);
        return std::move(r).error();
    }
    return sub->id;
}

Result<void> ClientLink::unsubscribe(SubscriptionId id) {
    std::lock_guard<std::mutex> lock(subscribe_mutex_);
    bool found = false;
    auto last = subscriptions_.remove(id, found);
    if (!found) return make_error(ErrorCode::node_not_exists, "no subscription " + std::to_string(id));
    if (!last.empty()) return transport_->unsubscribe(std::move(last));
    return ok_result();
}

}  // namespace nclink::client_detail
