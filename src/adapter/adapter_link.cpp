// The adapter's link to the broker and the agent (adapter_link.hpp): the
// retained online state (8.2.16), registration with an agent (8.2.1/8.2.2),
// Probe/Version (8.2.5) and the state machine that decides what is sent.
#include "adapter/adapter_link.hpp"

#include <fmt/format.h>

#include <functional>

namespace nclink::adapter_detail {

Message state_message(const std::string& dev, const char* state_text) {
    NotifyState notify;
    notify.tid = dev;
    notify.state = state_text;
    return Message{topics::notify_state(dev), encode(notify), 1, true};
}

AdapterLink::AdapterLink(const AdapterConfig& config, Transport& transport, const feature_detail::ModelSource& model,
                         std::shared_ptr<const Clock> clock, const Logger& logger, std::string dev, std::string instance,
                         std::function<void()> wake_housekeeping)
    : config_(config),
      transport_(transport),
      model_(model),
      clock_(std::move(clock)),
      logger_(logger),
      dev_(std::move(dev)),
      instance_(std::move(instance)),
      msg_id_prefix_(fmt::format("{}-{}-", dev_, instance_)),
      wake_housekeeping_(std::move(wake_housekeeping)),
      registration_(config.register_timeout, config.register_retry_max, std::hash<std::string>{}(msg_id_prefix_)),
      responses_(config.offline_buffer_bytes) {}

AdapterState AdapterLink::state() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
}

void AdapterLink::stopping() {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
}

// Thread: transport callback/supervisor thread. Never blocks. What a
// reconnection announces (state, registration, version) and when the kept
// responses go is the table's row, not code here.
void AdapterLink::on_link(LinkState link) {
    if (link == LinkState::connected) fire(AdapterEvent::link_restored);
    else if (link == LinkState::disconnected) fire(AdapterEvent::link_lost);
}

// The row is taken and the response kept under the state mutex, so a
// response handled while the link comes back is either kept before the
// flush takes the cache or sent after the state is normal again: never
// stranded in the cache.
void AdapterLink::fire(AdapterEvent event, std::vector<Message> response) {
    unsigned actions = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const AdapterState before = state_;
        const auto t = adapter_transition(before, event);
        actions = t.actions;
        state_ = t.next;
        // The transport reports "disconnected" before its first connection:
        // not a lost link worth a line.
        if (event == AdapterEvent::link_restored) connected_once_ = true;
        if (event == AdapterEvent::link_lost && !connected_once_)
            logger_.debug("adapter state: {} -> {} (waiting for the first connection)", to_string(before), to_string(t.next));
        else if (stopping_ && event == AdapterEvent::link_lost)
            // stop() closes the link itself: not a lost link either.
            logger_.debug("adapter state: {} -> {} (stopping)", to_string(before), to_string(t.next));
        else if (t.next != before)
            logger_.info("adapter state: {} -> {} ({})", to_string(before), to_string(t.next), to_string(event));
        if (actions & action_cache_response)
            for (auto& m : response) responses_.keep(std::move(m));
    }
    // In the row's order: who we are first, then what was kept (8.3.6: the
    // adapter registers again before anything else goes out).
    if (actions & action_announce_online) (void)transport_.publish(state_message(dev_, "online"));
    if (actions & action_register) send_registration();
    if (actions & action_announce_version) publish_version();
    if (actions & action_send_response) {
        std::vector<Message> failed;
        for (auto& m : response)
            if (!transport_.publish(m).ok()) failed.push_back(std::move(m));
        if (!failed.empty()) fire(AdapterEvent::response_failed, std::move(failed));
    }
    if (actions & action_flush_cached) flush_responses();
}

// Sends what was kept, oldest first. A response the link refuses again is
// kept again (unless it can never fit: larger than the whole buffer), and
// the state stays `request`; once all went, `cache_flushed` returns the
// adapter to `normal`.
void AdapterLink::flush_responses() {
    std::vector<Message> kept;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        kept = responses_.take_all();
    }
    std::vector<Message> failed;
    for (auto& m : kept) {
        auto sent = transport_.publish(m);
        if (sent.ok()) continue;
        if (sent.error().code == ErrorCode::memory_configured) {
            logger_.warn("response on {} dropped: larger than the offline buffer", m.topic);
            continue;
        }
        failed.push_back(std::move(m));
    }
    if (failed.empty()) {
        fire(AdapterEvent::cache_flushed);
        return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    // Back in front of anything kept meanwhile, in the original order.
    auto newer = responses_.take_all();
    for (auto& m : failed) responses_.keep(std::move(m));
    for (auto& m : newer) responses_.keep(std::move(m));
}

void AdapterLink::respond(const ParsedTopic& request_topic, const Json& reply) {
    // A registration's answer names this run of the adapter in privateInfo
    // (the implementation's, 8.2.18/8.2.28), as Probe/Version does: the
    // application then knows, after an outage, whether the registration is
    // still here (same run) or must be made again (docs/wire.md).
    if ((request_topic.kind == TopicKind::event_register_request || request_topic.kind == TopicKind::sample_register_request) &&
        reply.is_object() &&
        (!reply.contains("privateInfo") || reply["privateInfo"].is_object() || reply["privateInfo"].is_null())) {
        Json marked = reply;
        if (!marked["privateInfo"].is_object()) marked["privateInfo"] = Json::object();
        marked["privateInfo"]["instance"] = instance_;
        respond_text(request_topic, marked.dump(-1, ' ', false, Json::error_handler_t::replace));
        return;
    }
    respond_text(request_topic, reply.dump(-1, ' ', false, Json::error_handler_t::replace));
}

void AdapterLink::respond_text(const ParsedTopic& request_topic, std::string payload) {
    std::vector<Message> response;
    auto topics = response_topics(request_topic, config_.standard_typo_topics);
    response.reserve(topics.size());
    for (std::size_t i = 0; i < topics.size(); ++i)
        response.push_back(Message{std::move(topics[i]), i + 1 == topics.size() ? std::move(payload) : payload, 1, false});
    // Sent, or kept for later: the state machine's row decides (the state-machine text 69, 74, 79).
    fire(AdapterEvent::request_handled, std::move(response));
}

std::string AdapterLink::next_msg_id() { return msg_id_prefix_ + std::to_string(++msg_counter_); }

void AdapterLink::send_registration() {
    RegisterRequest request;
    // One @id for every Register/Request of this run: a retry, or a request
    // sent again after a reconnect the broker had in fact accepted, is the
    // same request (8.3.6), which an agent answers OK instead of refusing it
    // as a second live registration of the id (docs/agent.md).
    const std::string id = msg_id_prefix_ + "register";
    request.msg_id = Json(id);
    request.cli_uuid = dev_;
    registration_.sent(id, clock_->now());
    (void)transport_.publish(Message{topics::register_request(), encode(request), 1, false});
    wake_housekeeping_();
}

void AdapterLink::publish_version() {
    const auto current = model_.current();
    ProbeVersionRequest version;
    version.msg_id = Json(next_msg_id());
    version.guid = dev_;
    version.version = current->device->version;
    // privateInfo is the implementation's (8.2.5): which run of the adapter
    // this is, so an application can tell a restart (its registrations are
    // gone) from a broker or network outage (they are kept).
    version.private_info = Json{{"instance", instance_}};
    (void)transport_.publish(Message{topics::probe_version(dev_), encode(version), 1, false});
}

void AdapterLink::on_register_response(const std::string& payload) {
    auto response = decode<RegisterResponse>(payload);
    if (!response || response->cli_uuid != dev_) return;
    switch (registration_.answered(*response)) {
        case Registration::Answer::ignored: return;
        case Registration::Answer::accepted: logger_.info("registered with the agent as {}", dev_); break;
        case Registration::Answer::refused:
            logger_.error("the agent refused registration of {}: {} {}", dev_, response->status.error.value_or(0),
                          response->status.reason.value_or("(no reason)"));
            break;
    }
    wake_housekeeping_();
}

// Registers again when no agent answered in time, with a growing interval;
// the adapter serves all along (docs/wire.md: proceed if no agent answers).
void AdapterLink::tick_registration(Clock::Steady now) {
    const auto tick = registration_.tick(now, transport_.state() == LinkState::connected);
    if (tick.gave_up.count() > 0)
        // Said once at info; the retries that follow are routine.
        logger_.log(tick.first_give_up ? LogLevel::info : LogLevel::debug,
                    "no Register/Response from an agent within {} ms; serving anyway, retrying in {} ms",
                    config_.register_timeout.count(), tick.gave_up.count());
    if (tick.resend) send_registration();
}

void AdapterLink::retry_kept() {
    if (transport_.state() == LinkState::connected) fire(AdapterEvent::retry_due);
}

}  // namespace nclink::adapter_detail
