#include "client/subscriptions.hpp"

#include <nclink/topic_filter.hpp>

namespace nclink::client_detail {

std::shared_ptr<Subscription> SubscriptionRegistry::add(std::vector<std::string> filters, AnyHandler handler) {
    auto sub = std::make_shared<Subscription>();
    sub->filters = std::move(filters);
    sub->handler = std::move(handler);
    std::lock_guard<std::mutex> lock(mutex_);
    sub->id = next_id_++;
    by_id_.emplace(sub->id, sub);
    return sub;
}

std::vector<std::string> SubscriptionRegistry::remove(SubscriptionId id, bool& found) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_id_.find(id);
    found = it != by_id_.end();
    if (!found) return {};
    const std::vector<std::string> filters = it->second->filters;
    it->second->alive = false;
    by_id_.erase(it);
    std::vector<std::string> unused;
    for (const auto& filter : filters) {
        bool used = false;
        for (const auto& [other_id, other] : by_id_)
            for (const auto& f : other->filters) used = used || f == filter;
        if (!used) unused.push_back(filter);
    }
    return unused;
}

std::vector<std::shared_ptr<Subscription>> SubscriptionRegistry::matching(std::string_view topic) const {
    std::vector<std::shared_ptr<Subscription>> out;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, sub] : by_id_)
        for (const auto& filter : sub->filters)
            if (topic_matches(filter, topic)) {
                out.push_back(sub);
                break;
            }
    return out;
}

}  // namespace nclink::client_detail
