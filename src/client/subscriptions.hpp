// The application's subscriptions (samples, state, versions): which handler
// wants which topic filter, and when a broker subscription can go.
// Internally synchronized.
#pragma once

#include <nclink/client.hpp>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace nclink::client_detail {

using AnyHandler = std::variant<SampleHandler, StateHandler, VersionHandler>;

struct Subscription {
    SubscriptionId id = 0;
    std::string filter;
    AnyHandler handler;
    std::atomic<bool> alive{true};  ///< cleared by remove(), checked before each call
};

class SubscriptionRegistry {
public:
    std::shared_ptr<Subscription> add(std::string filter, AnyHandler handler);
    /// Removes a subscription; returns its filter when no other subscription
    /// uses it (the broker subscription can go), and false-y `found` when unknown.
    std::optional<std::string> remove(SubscriptionId id, bool& found);
    /// Live subscriptions whose filter matches `topic`, in subscription order.
    std::vector<std::shared_ptr<Subscription>> matching(std::string_view topic) const;

private:
    mutable std::mutex mutex_;
    SubscriptionId next_id_ = 1;
    std::map<SubscriptionId, std::shared_ptr<Subscription>> by_id_;
};

}  // namespace nclink::client_detail
