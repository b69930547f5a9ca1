// The client's side of the broker: the transport, the link's state as the
// transport reports it, and the application's subscriptions kept in step
// with the broker's (a filter is subscribed while any subscription uses it).
// Thread-safe: any thread may subscribe, unsubscribe, read or wait on the
// state; note() is called on the transport's callback thread.
#pragma once

#include "client/subscriptions.hpp"

#include <nclink/transport.hpp>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::client_detail {

class ClientLink {
public:
    explicit ClientLink(std::unique_ptr<Transport> transport) : transport_(std::move(transport)) {}

    Transport& transport() noexcept { return *transport_; }
    const Transport& transport() const noexcept { return *transport_; }

    LinkState state() const;
    bool connected() const { return state() == LinkState::connected; }
    /// True once the link is connected, false when `timeout` passed first.
    bool wait_connected(std::chrono::milliseconds timeout);
    /// Thread: transport callback. Records the state and wakes the waiters.
    void note(LinkState state);

    /// Subscribes again even when the filter is known: the broker then
    /// re-sends retained messages (the current state) for the new handler.
    Result<SubscriptionId> subscribe(std::vector<std::string> filters, AnyHandler handler);
    Result<SubscriptionId> subscribe(std::string filter, AnyHandler handler) {
        return subscribe(std::vector<std::string>{std::move(filter)}, std::move(handler));
    }
    /// node_not_exists for an unknown id; the broker subscriptions no other
    /// subscription uses go.
    Result<void> unsubscribe(SubscriptionId id);
    /// Live subscriptions whose filters match `topic`, in subscription order.
    std::vector<std::shared_ptr<Subscription>> matching(std::string_view topic) const { return subscriptions_.matching(topic); }

private:
    std::unique_ptr<Transport> transport_;
    std::mutex subscribe_mutex_;  // keeps the registry and the broker's subscriptions in step
    SubscriptionRegistry subscriptions_;
    mutable std::mutex state_mutex_;
    std::condition_variable state_changed_;
    LinkState state_ = LinkState::disconnected;
};

}  // namespace nclink::client_detail
