// The adapter's link to the broker and the other terminals: the retained
// online state (8.2.16), registration with an agent (8.2.1/8.2.2),
// Probe/Version (8.2.5), the seed-004 state machine, and application
// liveness (8.2.18.3).
#include "adapter/adapter_impl.hpp"

namespace nclink {

// Thread: transport callback/supervisor thread. Never blocks.
void Adapter::Impl::on_link(LinkState link, std::string_view) {
    if (link == LinkState::connected) {
        (void)transport->publish(state_message("online"));
        send_registration();
        publish_version();
        fire(AdapterEvent::link_restored);
    } else if (link == LinkState::disconnected) {
        fire(AdapterEvent::link_lost);
    }
    for (auto& feature : features) feature->on_link(link);
}

void Adapter::Impl::fire(AdapterEvent event) {
    std::lock_guard<std::mutex> lock(mutex);
    const auto t = adapter_transition(state, event);
    if (t.next != state) logger.info("adapter state: {} -> {} ({})", to_string(state), to_string(t.next), to_string(event));
    state = t.next;
}

std::string Adapter::Impl::next_msg_id() { return msg_id_prefix + std::to_string(++msg_counter); }

void Adapter::Impl::send_registration() {
    RegisterRequest request;
    const std::string id = next_msg_id();
    request.msg_id = Json(id);
    request.cli_uuid = dev;
    registration.sent(id, clock->now());
    (void)transport->publish(Message{topics::register_request(), encode(request), 1, false});
    housekeeping_wake.notify_all();
}

void Adapter::Impl::publish_version() {
    const auto current = host.current();
    ProbeVersionRequest version;
    version.msg_id = Json(next_msg_id());
    version.guid = dev;
    version.version = current->device->version;
    (void)transport->publish(Message{topics::probe_version(dev), encode(version), 1, false});
}

// Thread: housekeeping. Registers again when no agent answered in time, with
// a growing interval; the adapter serves all along (docs/wire.md: proceed if
// no agent answers). Releases what silent applications registered. Polls the
// injected clock every 50 ms, so tests drive it with a ManualClock.
void Adapter::Impl::housekeep() {
    std::unique_lock<std::mutex> lock(housekeeping_mutex);
    while (!housekeeping_stopping) {
        const auto now = clock->now();
        lock.unlock();
        const auto tick = registration.tick(now, transport->state() == LinkState::connected);
        if (tick.gave_up.count() > 0)
            // Said once at info; the retries that follow are routine.
            logger.log(tick.first_give_up ? LogLevel::info : LogLevel::debug,
                       "no Register/Response from an agent within {} ms; serving anyway, retrying in {} ms",
                       config.register_timeout.count(), tick.gave_up.count());
        if (tick.resend) send_registration();
        for (const auto& ex : applications->expire(now)) application_gone(ex, "silent for the application lease");
        lock.lock();
        if (housekeeping_stopping) break;
        housekeeping_wake.wait_for(lock, std::chrono::milliseconds(50));
    }
}

void Adapter::Impl::on_register_response(const std::string& payload) {
    auto response = decode<RegisterResponse>(payload);
    if (!response || response->cli_uuid != dev) return;
    switch (registration.answered(*response)) {
        case detail::Registration::Answer::ignored: return;
        case detail::Registration::Answer::accepted: logger.info("registered with the agent as {}", dev); break;
        case detail::Registration::Answer::refused:
            logger.error("the agent refused registration of {}: {} {}", dev, response->status.error.value_or(0),
                         response->status.reason.value_or("(no reason)"));
            break;
    }
    housekeeping_wake.notify_all();
}

void Adapter::Impl::application_gone(const std::string& ex, std::string_view why) {
    logger.info("application {} is gone ({}): releasing its channels and events", ex, why);
    for (auto& feature : features) feature->on_application_gone(ex);
}

void Adapter::Impl::on_notify_state(const ParsedTopic& topic, const std::string& payload) {
    if (topic.dev == dev) return;
    auto notify = decode<NotifyState>(payload);
    if (!notify || notify->state != "offline") return;
    if (applications->gone(topic.dev)) application_gone(topic.dev, "Notify/State offline");
}

}  // namespace nclink
