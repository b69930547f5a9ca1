// The client's engine: transport callbacks handed to the dispatch thread,
// responses matched to pending requests by @id, notifications delivered to
// subscriptions, deadlines expired (client_impl.hpp).
#include "client/client_impl.hpp"
#include "client/client_methods.hpp"

#include <fmt/format.h>

namespace nclink {

using client_detail::safely;

namespace {

bool is_client_response(TopicKind kind) {
    switch (kind) {
        case TopicKind::register_response:
        case TopicKind::discovery_response:
        case TopicKind::probe_query_response:
        case TopicKind::probe_set_response:
        case TopicKind::query_response:
        case TopicKind::method_result:               // client_methods.cpp
        case TopicKind::method_control_response:     // client_methods.cpp
        case TopicKind::sample_register_response:    // client_sampling.cpp
        case TopicKind::sample_unregister_response:  // client_sampling.cpp
        case TopicKind::event_register_response:     // client_events.cpp
        case TopicKind::event_unregister_response:   // client_events.cpp
        case TopicKind::set_response: return true;
        default: return false;
    }
}

}  // namespace

std::vector<std::string> Client::Impl::response_filters() const {
    const std::string& ex = options.ex_cid;
    return {topics::register_response(ex),
            topics::discovery_response(ex),
            topics::probe_query_response("+", ex),
            topics::probe_set_response("+", ex),
            topics::query_response("+", ex),
            topics::set_response("+", ex),
            topics::method_result("+", ex),
            topics::method_status("+", ex),  // client_methods.cpp
            topics::method_control_response("+", ex),
            topics::sample_register_response("+", ex),
            topics::sample_unregister_response("+", ex),  // client_sampling.cpp
            topics::event_register_response("+", ex),
            topics::event_unregister_response("+", ex),  // client_events.cpp
            topics::event("+", ex)};
}

Result<void> Client::Impl::start() {
    std::lock_guard<std::mutex> lock(lifecycle_mutex);
    if (started) return make_error(ErrorCode::unavailable, "client already started");
    started = true;
    Transport& transport = link.transport();
    transport.set_message_handler([this](const Message& m) { on_message(m); });
    transport.set_state_handler([this](LinkState s, std::string_view detail) { on_link(s, detail); });
    dispatcher.start();
    // Before the first request can go out: responses must find us subscribed.
    if (auto r = transport.subscribe(response_filters(), 1); !r) {
        dispatcher.stop();
        return r;
    }
    if (auto r = transport.start(); !r) {
        dispatcher.stop();
        return r;
    }
    return ok_result();
}

void Client::Impl::stop() {
    if (dispatcher.on_dispatch_thread()) {
        log.error("client: stop() called from a client callback; ignored");
        return;
    }
    {
        std::lock_guard<std::mutex> lock(lifecycle_mutex);
        if (stopped) return;
        stopped = true;
        if (!started) return;
    }
    link.transport().stop(options.stop_flush_timeout);  // no transport callbacks after this
    dispatcher.stop();                                  // runs what is queued, then fails what is pending
}

// ---- transport callback thread: copy and hand over, never block ----
void Client::Impl::on_message(const Message& m) {
    if (!dispatcher.post([this, m] { handle_message(m); })) log.debug("client: message on {} after stop dropped", m.topic);
}

void Client::Impl::on_link(LinkState state, std::string_view detail) {
    // The state machine first: wait_connected() returns into state normal.
    if (state == LinkState::connected) {
        for (auto& [id, error] : machine.link_restored()) fail_request(id, std::move(error));
    } else if (state == LinkState::disconnected) {
        machine.link_lost();
    }
    link.note(state);
    if (state == LinkState::connected) {
        keep_alive.all_due(Clock::now());  // the outage may have eaten most of the adapter's lease
        dispatcher.poke();
    }
    log.debug("client {}: link {} ({})", options.ex_cid, to_string(state), detail);
    if (options.on_link_state) dispatcher.post([this, state] { safely(log, [&] { options.on_link_state(state); }); });
}

// ---- dispatch thread ----
void Client::Impl::handle_message(const Message& m) {
    const auto parsed = parse_topic(m.topic);
    if (!parsed) {
        ++counters.unmatched;
        return;
    }
    if (parsed->kind == TopicKind::event) {
        handle_event(*parsed, m);
        return;
    }
    if (parsed->kind == TopicKind::method_status || parsed->kind == TopicKind::method_result) {
        handle_method_run(*parsed, m);
        return;
    }
    if (is_client_response(parsed->kind)) handle_response(*parsed, m.payload);
    else handle_notification(*parsed, m);
}

void Client::Impl::handle_event(const ParsedTopic& topic, const Message& m) {
    // The last level names the application that registered (8.2.31); a
    // topic without it can only be ours.
    const bool own = !topic.ex || *topic.ex == options.ex_cid;
    // A QoS 1 repeat, or a second copy from a broker that sends one per
    // overlapping subscription (ours and a subscribe_events one; MQTT 3.1.1
    // 3.3.5 allows it), is handed on once (client_liveness.cpp).
    if (const MessageId id = peek_message_id(m.payload);
        id && !first_delivery("E/" + topic.dev + "/" + topic.ex.value_or(""), id->dump()))
        return;
    if (own) {  // client_events.cpp
        const auto delivery = event_routes.deliver(topic.dev, m.payload, log);
        ++(delivery == client_detail::EventRoutes::Delivery::delivered   ? counters.events
           : delivery == client_detail::EventRoutes::Delivery::malformed ? counters.malformed
                                                                         : counters.unmatched);
    }
    const auto subs = link.matching(m.topic);
    if (subs.empty()) return;
    auto dtu = decode<EventData>(std::string_view(m.payload));
    if (!dtu) {
        if (!own) ++counters.malformed;  // an own one was counted above
        return;
    }
    WatchedEvent watched;
    watched.dev = topic.dev;
    watched.ex = topic.ex.value_or("");
    watched.event = std::move(dtu).value();
    if (watched.event.guid.empty()) watched.event.guid = topic.dev;
    deliver_to<WatchedEventHandler>(subs, watched, counters.events);
}

void Client::Impl::handle_method_run(const ParsedTopic& topic, const Message& m) {
    // As for events: a topic without the caller's level can only be ours.
    const bool own = !topic.ex || *topic.ex == options.ex_cid;
    const bool is_result = topic.kind == TopicKind::method_result;
    // One Method/Result per call (8.2.24): a second copy (QoS 1 repeat, or
    // one per overlapping subscription) is dropped. Method/Status DTUs are
    // not: identical ones legitimately repeat every status period (8.2.23).
    if (is_result) {
        if (const MessageId id = peek_message_id(m.payload); id && !first_delivery("R/" + m.topic, id->dump())) return;
    }
    if (own) {
        if (is_result) handle_response(topic, m.payload);
        else client_detail::handle_method_status(pending, m.payload, log);  // client_methods.cpp
    }
    const auto subs = link.matching(m.topic);
    if (subs.empty()) return;
    MethodRun run;
    run.dev = topic.dev;
    run.ex = topic.ex.value_or("");
    if (is_result) {
        auto dtu = decode<MethodResult>(std::string_view(m.payload));
        if (!dtu) {
            if (!own) ++counters.malformed;  // an own one was counted by handle_response
            return;
        }
        if (dtu->guid.empty()) dtu->guid = topic.dev;
        run.kind = MethodRun::Kind::result;
        run.result = std::move(dtu).value();
    } else {
        auto dtu = decode<MethodStatus>(std::string_view(m.payload));
        if (!dtu) {
            ++counters.malformed;
            return;
        }
        if (dtu->guid.empty()) dtu->guid = topic.dev;
        run.kind = MethodRun::Kind::status;
        run.status = std::move(dtu).value();
    }
    deliver_to<MethodRunHandler>(subs, run, counters.notifications);
}

void Client::Impl::handle_response(const ParsedTopic& topic, const std::string& payload) {
    const MessageId msg_id = peek_message_id(payload);
    if (!msg_id) {
        ++counters.malformed;
        log.debug("client: response on {} without a usable @id dropped", build_topic(topic));
        return;
    }
    const std::string key = msg_id->is_string() ? msg_id->get<std::string>() : msg_id->dump();
    TopicKind expected = TopicKind::query_response;
    const std::shared_ptr<client_detail::Responder> responder = pending.peek(key, &expected);
    if (!responder) {
        if (pending.timed_out_recently(key)) {
            ++counters.late;
            log.debug("client: late response {} dropped", key);
        } else {
            ++counters.unmatched;
        }
        return;
    }
    if (auto unreachable = client_detail::unreachable_error(payload)) {
        if (auto taken = pending.take(key)) {
            ++counters.unreachable;
            safely(log, [&] { taken->responder->fail(std::move(*unreachable)); });
        }
        return;
    }
    if (expected != topic.kind) {
        ++counters.unmatched;  // same @id on another kind of response: not ours
        return;
    }
    if (topic.kind == TopicKind::event_register_response || topic.kind == TopicKind::sample_register_response)
        note_instance(topic.dev, payload);  // client_model_cache.cpp
    if (!responder->decode(payload)) {
        ++counters.malformed;
        log.warn("client: malformed response {} on {} ignored", key, build_topic(topic));
        return;
    }
    if (auto taken = pending.take(key)) {
        ++counters.responses;
        safely(log, [&] { taken->responder->complete(); });
    }
}

void Client::Impl::handle_notification(const ParsedTopic& topic, const Message& m) {
    const auto subs = link.matching(m.topic);
    if (subs.empty()) return;
    switch (topic.kind) {
        case TopicKind::sample:
        case TopicKind::dynamic_sample: {  // client_sampling.cpp filters by channel
            auto dtu = decode<SampleDtu>(m.payload);
            if (!dtu) {
                ++counters.malformed;
                return;
            }
            if (dtu->guid.empty()) dtu->guid = topic.dev;
            if (!first_delivery(m.topic, dtu->id + "@" + std::to_string(dtu->begin_time)))
                return;  // a QoS 1 repeat (client_liveness.cpp)
            deliver_to<SampleHandler>(subs, *dtu, counters.samples);
            break;
        }
        case TopicKind::notify_state: {
            if (m.payload.empty()) {  // a cleared retained state
                known_states.erase(topic.dev);
                return;
            }
            auto dtu = decode<NotifyState>(m.payload);
            if (!dtu) {
                ++counters.malformed;
                return;
            }
            if (dtu->tid.empty()) dtu->tid = topic.dev;
            known_states[topic.dev] = dtu->state;
            deliver_to<StateHandler>(subs, *dtu, counters.notifications);
            break;
        }
        case TopicKind::probe_version: {
            auto dtu = decode<ProbeVersionRequest>(m.payload);
            if (!dtu) {
                ++counters.malformed;
                return;
            }
            if (dtu->guid.empty()) dtu->guid = topic.dev;
            deliver_to<VersionHandler>(subs, *dtu, counters.notifications);
            break;
        }
        default: ++counters.unmatched; break;
    }
}

void Client::Impl::expire(Clock::time_point now) {
    for (auto& request : pending.take_expired(now)) {
        ++counters.timeouts;
        log.debug("client: request {} timed out", request.id);
        safely(log, [&] {
            std::string message = "no response to " + request.id + " in time";
            // What the broker retained of the terminal says why, when known.
            if (const auto it = known_states.find(request.dev); it != known_states.end() && it->second != "online")
                message +=
                    fmt::format(" (device {} is {}: its retained Notify/State/{} says so)", request.dev, it->second, request.dev);
            request.responder->fail(make_error(ErrorCode::timeout, message));
        });
    }
}

void Client::Impl::fail_all() {
    for (auto& request : pending.close())
        safely(log, [&] { request.responder->fail(make_error(ErrorCode::unavailable, "client stopped")); });
}

// Fails a pending request whose publish failed; on the dispatch thread when it runs.
void Client::Impl::fail_request(const std::string& id, Error error) {
    if (auto taken = pending.take(id)) {
        auto task = [this, r = std::move(taken->responder), error]() mutable { safely(log, [&] { r->fail(std::move(error)); }); };
        if (!dispatcher.post(task)) task();
    }
}

}  // namespace nclink
