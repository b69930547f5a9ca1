// Application liveness (adapter_applications.hpp).
#include "adapter/adapter_applications.hpp"

#include <nclink/dtu.hpp>

#include <fmt/format.h>

namespace nclink::adapter_detail {

ApplicationWatch::ApplicationWatch(Transport& transport, std::string dev, std::chrono::milliseconds lease, const Logger& logger,
                                   std::function<void(const std::string&)> gone)
    : transport_(transport), dev_(std::move(dev)), lease_(lease), logger_(logger), on_gone_(std::move(gone)), tracker_(lease) {}

// Subscribes the Notify/State of an application that just sent its first
// DTU, to release what it registered when it goes offline. Not
// Notify/State/+: that would bring every terminal's retained state to every
// adapter, N x N messages when a plant of N terminals (re)connects.
void ApplicationWatch::seen(const std::string& ex, Clock::Steady now) {
    if (!tracker_.seen(ex, now) || ex == dev_) return;
    (void)transport_.subscribe({topics::notify_state(ex)}, 1);
}

void ApplicationWatch::on_notify_state(const ParsedTopic& topic, const std::string& payload) {
    if (topic.dev == dev_) return;
    auto notify = decode<NotifyState>(payload);
    if (!notify || notify->state != "offline") return;
    if (tracker_.gone(topic.dev)) {
        (void)transport_.unsubscribe({topics::notify_state(topic.dev)});
        gone(topic.dev, "Notify/State offline");
    }
}

void ApplicationWatch::expire(Clock::Steady now) {
    for (const auto& ex : tracker_.expire(now)) {
        (void)transport_.unsubscribe({topics::notify_state(ex)});
        gone(ex, fmt::format("no DTU from it for the application lease of {} ms", lease_.count()));
    }
}

// 3.22: the application is offline for this adapter. Said in the log and
// counted (AdapterStats::applications_released). Not on the wire: the
// standard's place for a terminal's state, Notify/State (8.2.16), is the
// agent's to publish, and every other adapter would release that
// application's registrations on it although it may still talk to them
// (docs/delivery.md, "Liveness").
void ApplicationWatch::gone(const std::string& ex, std::string_view why) {
    ++released_;
    logger_.info("application {} is offline ({}): releasing its dynamic channels and events", ex, why);
    on_gone_(ex);
}

}  // namespace nclink::adapter_detail
