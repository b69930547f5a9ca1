// The shared-subscription check (shared_subscription_check.hpp).
#include "agent/shared_subscription_check.hpp"

#include <condition_variable>
#include <mutex>

#include <fmt/format.h>

namespace nclink::agent_detail {

SharedSubscriptionCheck check_shared_subscriptions(Transport& probe, const std::string& group, const std::string& topic,
                                                   std::chrono::milliseconds connect_timeout, std::chrono::milliseconds timeout) {
    struct Seen {
        std::mutex mutex;
        std::condition_variable changed;
        bool connected = false;
        bool lost = false;  // the link ended after it was up
        bool delivered = false;
    };
    auto seen = std::make_shared<Seen>();
    probe.set_message_handler([seen, topic](const Message& m) {
        if (m.topic != topic) return;
        std::lock_guard<std::mutex> lock(seen->mutex);
        seen->delivered = true;
        seen->changed.notify_all();
    });
    probe.set_state_handler([seen](LinkState s, std::string_view) {
        std::lock_guard<std::mutex> lock(seen->mutex);
        if (s == LinkState::connected) seen->connected = true;
        else if (s == LinkState::disconnected && seen->connected) seen->lost = true;
        seen->changed.notify_all();
    });
    SharedSubscriptionCheck check;
    auto finish = [&](SharedSubscriptions result, std::string detail) {
        probe.stop(std::chrono::milliseconds(0));
        check.result = result;
        check.detail = std::move(detail);
        return check;
    };
    if (auto started = probe.start(); !started) return finish(SharedSubscriptions::unknown, started.error().describe());
    {
        std::unique_lock<std::mutex> lock(seen->mutex);
        if (!seen->changed.wait_for(lock, connect_timeout, [&] { return seen->connected; }))
            return finish(SharedSubscriptions::unknown, fmt::format("not connected within {} ms", connect_timeout.count()));
    }
    const std::string filter = "$share/" + group + "-check/" + topic;
    if (auto subscribed = probe.subscribe({filter}, 1); !subscribed)
        return finish(SharedSubscriptions::unavailable, "SUBSCRIBE " + filter + ": " + subscribed.error().describe());
    // The SUBSCRIBE is on its way, not acknowledged: publish again until the
    // subscription delivers (a message before it takes effect is lost).
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::unique_lock<std::mutex> lock(seen->mutex);
    while (!seen->delivered && !seen->lost && std::chrono::steady_clock::now() < deadline) {
        lock.unlock();
        // Refused only while the link is down, which `lost` tells below.
        (void)probe.publish(Message{topic, "share-check", 0, false});
        lock.lock();
        seen->changed.wait_for(lock, std::chrono::milliseconds(100), [&] { return seen->delivered || seen->lost; });
    }
    const bool delivered = seen->delivered, lost = seen->lost;
    lock.unlock();
    if (delivered) return finish(SharedSubscriptions::available, "a message came through " + filter);
    if (lost) return finish(SharedSubscriptions::unavailable, "the broker ended the connection at SUBSCRIBE " + filter);
    return finish(SharedSubscriptions::unavailable, fmt::format("nothing came through {} within {} ms", filter, timeout.count()));
}

}  // namespace nclink::agent_detail
