// The application's subscriptions (samples, state, versions, method runs,
// events): which handler wants which topic filters, and when a broker
// subscription can go.
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

using AnyHandler = std::variant<SampleHandler, StateHandler, VersionHandler, MethodRunHandler, WatchedEventHandler>;

struct Subscription {
    SubscriptionId id = 0;
    std::vector<std::string> filters;  ///< one or more (method runs: status and result)
    AnyHandler handler;
    std::atomic<bool> alive{true};  ///< cleared by remove(), checked before each call
};

class SubscriptionRegistry {
public:
    std::shared_ptr<Subscription> add(std::vector<std::string> filters, AnyHandler handler);
    /// Removes a subscription; returns those of its filters no other
    /// subscription uses (their broker subscriptions can go), and false-y
    /// `found` when unknown.
    std::vector<std::string> remove(SubscriptionId id, bool& found);
    /// Live subscriptions with a filter that matches `topic`, in subscription order.
    std::vector<std::shared_ptr<Subscription>> matching(std::string_view topic) const;

private:
    mutable std::mutex mutex_;
    SubscriptionId next_id_ = 1;
    std::map<SubscriptionId, std::shared_ptr<Subscription>> by_id_;
};

}  // namespace nclink::client_detail
