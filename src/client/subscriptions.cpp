#include "client/subscriptions.hpp"

#include <nclink/topic_filter.hpp>

namespace nclink::client_detail {

std::shared_ptr<Subscription> SubscriptionRegistry::add(std::string filter, AnyHandler handler) {
    auto sub = std::make_shared<Subscription>();
    sub->filter = std::move(filter);
    sub->handler = std::move(handler);
    std::lock_guard<std::mutex> lock(mutex_);
    sub->id = next_id_++;
    by_id_.emplace(sub->id, sub);
    return sub;
}

std::optional<std::string> SubscriptionRegistry::remove(SubscriptionId id, bool& found) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_id_.find(id);
    found = it != by_id_.end();
    if (!found) return std::nullopt;
    std::string filter = it->second->filter;
    it->second->alive = false;
    by_id_.erase(it);
    for (const auto& [other_id, other] : by_id_)
        if (other->filter == filter) return std::nullopt;
    return filter;
}

std::vector<std::shared_ptr<Subscription>> SubscriptionRegistry::matching(std::string_view topic) const {
    std::vector<std::shared_ptr<Subscription>> out;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, sub] : by_id_)
        if (topic_matches(sub->filter, topic)) out.push_back(sub);
    return out;
}

}  // namespace nclink::client_detail
