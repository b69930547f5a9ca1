// The adapter's link to the broker and the other terminals: the retained
// online state (8.2.16), registration with an agent (8.2.1/8.2.2),
// Probe/Version (8.2.5), the state-machine state machine, and application
// liveness (8.2.18.3).
#include "adapter/adapter_impl.hpp"
#include "core/shared_threads_impl.hpp"

namespace nclink {

// Thread: transport callback/supervisor thread. Never blocks. What a
// reconnection announces (state, registration, version) and when the kept
// responses go is the table's row, not code here.
void Adapter::Impl::on_link(LinkState link, std::string_view) {
    if (link == LinkState::connected)
        fire(AdapterEvent::link_restored);
    else if (link == LinkState::disconnected)
        fire(AdapterEvent::link_lost);
    for (auto& feature : features) feature->on_link(link);
}

// The row is taken and the response kept under the state mutex, so a
// response handled while the link comes back is either kept before the
// flush takes the cache or sent after the state is normal again: never
// stranded in the cache.
void Adapter::Impl::fire(AdapterEvent event, std::vector<Message> response) {
    unsigned actions = 0;
    {
        std::lock_guard<std::mutex> lock(mutex);
        const AdapterState before = state;
        const auto t = adapter_transition(before, event);
        actions = t.actions;
        state = t.next;
        // The transport reports "disconnected" before its first connection:
        // not a lost link worth a line.
        if (event == AdapterEvent::link_restored) connected_once = true;
        if (event == AdapterEvent::link_lost && !connected_once)
            logger.debug("adapter state: {} -> {} (waiting for the first connection)", to_string(before), to_string(t.next));
        else if (stopped && event == AdapterEvent::link_lost)
            // stop() closes the link itself: not a lost link either.
            logger.debug("adapter state: {} -> {} (stopping)", to_string(before), to_string(t.next));
        else if (t.next != before)
            logger.info("adapter state: {} -> {} ({})", to_string(before), to_string(t.next), to_string(event));
        if (actions & action_cache_response)
            for (auto& m : response) responses.keep(std::move(m));
    }
    // In the row's order: who we are first, then what was kept (8.3.6: the
    // adapter registers again before anything else goes out).
    if (actions & action_announce_online) (void)transport->publish(state_message("online"));
    if (actions & action_register) send_registration();
    if (actions & action_announce_version) publish_version();
    if (actions & action_send_response) {
        std::vector<Message> failed;
        for (auto& m : response)
            if (!transport->publish(m).ok()) failed.push_back(std::move(m));
        if (!failed.empty()) fire(AdapterEvent::response_failed, std::move(failed));
    }
    if (actions & action_flush_cached) flush_responses();
}

// Sends what was kept, oldest first. A response the link refuses again is
// kept again (unless it can never fit: larger than the whole buffer), and
// the state stays `request`; once all went, `cache_flushed` returns the
// adapter to `normal`.
void Adapter::Impl::flush_responses() {
    std::vector<Message> kept;
    {
        std::lock_guard<std::mutex> lock(mutex);
        kept = responses.take_all();
    }
    std::vector<Message> failed;
    for (auto& m : kept) {
        auto sent = transport->publish(m);
        if (sent.ok()) continue;
        if (sent.error().code == ErrorCode::memory_configured) {
            logger.warn("response on {} dropped: larger than the offline buffer", m.topic);
            continue;
        }
        failed.push_back(std::move(m));
    }
    if (failed.empty()) {
        fire(AdapterEvent::cache_flushed);
        return;
    }
    std::lock_guard<std::mutex> lock(mutex);
    // Back in front of anything kept meanwhile, in the original order.
    auto newer = responses.take_all();
    for (auto& m : failed) responses.keep(std::move(m));
    for (auto& m : newer) responses.keep(std::move(m));
}

std::string Adapter::Impl::next_msg_id() { return msg_id_prefix + std::to_string(++msg_counter); }

void Adapter::Impl::send_registration() {
    RegisterRequest request;
    // One @id for every Register/Request of this run: a retry, or a request
    // sent again after a reconnect the broker had in fact accepted, is the
    // same request (8.3.6), which an agent answers OK instead of refusing it
    // as a second live registration of the id (docs/agent.md).
    const std::string id = msg_id_prefix + "register";
    request.msg_id = Json(id);
    request.cli_uuid = dev;
    registration.sent(id, clock->now());
    (void)transport->publish(Message{topics::register_request(), encode(request), 1, false});
    wake_housekeeping();
}

void Adapter::Impl::publish_version() {
    const auto current = host.current();
    ProbeVersionRequest version;
    version.msg_id = Json(next_msg_id());
    version.guid = dev;
    version.version = current->device->version;
    // privateInfo is the implementation's (8.2.5): which run of the adapter
    // this is, so an application can tell a restart (its registrations are
    // gone) from a broker or network outage (they are kept).
    version.private_info = Json{{"instance", instance}};
    (void)transport->publish(Message{topics::probe_version(dev), encode(version), 1, false});
}

// Thread: housekeeping. Registers again when no agent answered in time, with
// a growing interval; the adapter serves all along (docs/wire.md: proceed if
// no agent answers). Releases what silent applications registered. Polls the
// injected clock every 50 ms, so tests drive it with a ManualClock.
void Adapter::Impl::housekeep() {
    std::unique_lock<std::mutex> lock(housekeeping_mutex);
    while (!housekeeping_stopping) {
        lock.unlock();
        housekeep_once();
        lock.lock();
        if (housekeeping_stopping) break;
        housekeeping_wake.wait_for(lock, kHousekeepingPeriod);
    }
}

void Adapter::Impl::housekeep_once() {
    const auto now = clock->now();
    const auto tick = registration.tick(now, transport->state() == LinkState::connected);
    if (tick.gave_up.count() > 0)
        // Said once at info; the retries that follow are routine.
        logger.log(tick.first_give_up ? LogLevel::info : LogLevel::debug,
                   "no Register/Response from an agent within {} ms; serving anyway, retrying in {} ms",
                   config.register_timeout.count(), tick.gave_up.count());
    if (tick.resend) send_registration();
    for (const auto& ex : applications->expire(now)) {
        (void)transport->unsubscribe({topics::notify_state(ex)});
        application_gone(ex, fmt::format("no DTU from it for the application lease of {} ms", config.application_lease.count()));
    }
    if (transport->state() == LinkState::connected) fire(AdapterEvent::retry_due);
    // Once a second (real time: the statistics are not cheap): every
    // loss logged once per burst (drop_reporter.hpp).
    if (const auto real = std::chrono::steady_clock::now(); real - last_drop_check >= std::chrono::seconds(1)) {
        last_drop_check = real;
        if (features_ready.load(std::memory_order_acquire)) drop_reporter.observe(drops_now());
    }
}

void Adapter::Impl::wake_housekeeping() {
    if (shared_threads) {
        shared_threads->impl().timers.wake(housekeeping_entry);
        return;
    }
    housekeeping_wake.notify_all();
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
    wake_housekeeping();
}

// 3.22: the application is offline for this adapter. Said in the log and
// counted (AdapterStats::applications_released). Not on the wire: the
// standard's place for a terminal's state, Notify/State (8.2.16), is the
// agent's to publish, and every other adapter would release that
// application's registrations on it although it may still talk to them
// (docs/delivery.md, "Liveness").
void Adapter::Impl::application_gone(const std::string& ex, std::string_view why) {
    ++applications_released;
    logger.info("application {} is offline ({}): releasing its dynamic channels and events", ex, why);
    for (auto& feature : features) feature->on_application_gone(ex);
}

void Adapter::Impl::on_notify_state(const ParsedTopic& topic, const std::string& payload) {
    if (topic.dev == dev) return;
    auto notify = decode<NotifyState>(payload);
    if (!notify || notify->state != "offline") return;
    if (applications->gone(topic.dev)) {
        (void)transport->unsubscribe({topics::notify_state(topic.dev)});
        application_gone(topic.dev, "Notify/State offline");
    }
}

void Adapter::Impl::watch_application(const std::string& ex) {
    if (ex == dev) return;
    (void)transport->subscribe({topics::notify_state(ex)}, 1);
}

}  // namespace nclink
