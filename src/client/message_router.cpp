// The client's receive side (message_router.hpp): every DTU routed on the
// dispatch thread to a pending request, an own registration or call, and the
// matching subscriptions.
#include "client/message_router.hpp"
#include "client/client_methods.hpp"
#include "client/responders.hpp"

#include <nclink/dtu.hpp>

namespace nclink::client_detail {

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

std::vector<std::string> MessageRouter::response_filters(const std::string& ex) {
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

void MessageRouter::route(const Message& m) {
    const auto parsed = parse_topic(m.topic);
    if (!parsed) {
        ++p_.counters.unmatched;
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

void MessageRouter::handle_event(const ParsedTopic& topic, const Message& m) {
    // The last level names the application that registered (8.2.31); a
    // topic without it can only be ours.
    const bool own = !topic.ex || *topic.ex == p_.ex_cid;
    // A QoS 1 repeat, or a second copy from a broker that sends one per
    // overlapping subscription (ours and a subscribe_events one; MQTT 3.1.1
    // 3.3.5 allows it), is handed on once (client_liveness.cpp).
    if (const MessageId id = peek_message_id(m.payload);
        id && !first_delivery("E/" + topic.dev + "/" + topic.ex.value_or(""), id->dump()))
        return;
    if (own) {  // client_events.cpp
        const auto delivery = p_.event_routes.deliver(topic.dev, m.payload, p_.log);
        ++(delivery == EventRoutes::Delivery::delivered   ? p_.counters.events
           : delivery == EventRoutes::Delivery::malformed ? p_.counters.malformed
                                                          : p_.counters.unmatched);
    }
    const auto subs = p_.link.matching(m.topic);
    if (subs.empty()) return;
    auto dtu = decode<EventData>(std::string_view(m.payload));
    if (!dtu) {
        if (!own) ++p_.counters.malformed;  // an own one was counted above
        return;
    }
    WatchedEvent watched;
    watched.dev = topic.dev;
    watched.ex = topic.ex.value_or("");
    watched.event = std::move(dtu).value();
    if (watched.event.guid.empty()) watched.event.guid = topic.dev;
    deliver_to<WatchedEventHandler>(subs, watched, p_.counters.events);
}

void MessageRouter::handle_method_run(const ParsedTopic& topic, const Message& m) {
    // As for events: a topic without the caller's level can only be ours.
    const bool own = !topic.ex || *topic.ex == p_.ex_cid;
    const bool is_result = topic.kind == TopicKind::method_result;
    // One Method/Result per call (8.2.24): a second copy (QoS 1 repeat, or
    // one per overlapping subscription) is dropped. Method/Status DTUs are
    // not: identical ones legitimately repeat every status period (8.2.23).
    if (is_result) {
        if (const MessageId id = peek_message_id(m.payload); id && !first_delivery("R/" + m.topic, id->dump())) return;
    }
    if (own) {
        if (is_result) handle_response(topic, m.payload);
        else handle_method_status(p_.pending, m.payload, p_.log);  // client_methods.cpp
    }
    const auto subs = p_.link.matching(m.topic);
    if (subs.empty()) return;
    MethodRun run;
    run.dev = topic.dev;
    run.ex = topic.ex.value_or("");
    if (is_result) {
        auto dtu = decode<MethodResult>(std::string_view(m.payload));
        if (!dtu) {
            if (!own) ++p_.counters.malformed;  // an own one was counted by handle_response
            return;
        }
        if (dtu->guid.empty()) dtu->guid = topic.dev;
        run.kind = MethodRun::Kind::result;
        run.result = std::move(dtu).value();
    } else {
        auto dtu = decode<MethodStatus>(std::string_view(m.payload));
        if (!dtu) {
            ++p_.counters.malformed;
            return;
        }
        if (dtu->guid.empty()) dtu->guid = topic.dev;
        run.kind = MethodRun::Kind::status;
        run.status = std::move(dtu).value();
    }
    deliver_to<MethodRunHandler>(subs, run, p_.counters.notifications);
}

void MessageRouter::handle_response(const ParsedTopic& topic, const std::string& payload) {
    const MessageId msg_id = peek_message_id(payload);
    if (!msg_id) {
        ++p_.counters.malformed;
        p_.log.debug("client: response on {} without a usable @id dropped", build_topic(topic));
        return;
    }
    const std::string key = msg_id->is_string() ? msg_id->get<std::string>() : msg_id->dump();
    TopicKind expected = TopicKind::query_response;
    const std::shared_ptr<Responder> responder = p_.pending.peek(key, &expected);
    if (!responder) {
        if (p_.pending.timed_out_recently(key)) {
            ++p_.counters.late;
            p_.log.debug("client: late response {} dropped", key);
        } else {
            ++p_.counters.unmatched;
        }
        return;
    }
    if (auto unreachable = unreachable_error(payload)) {
        if (auto taken = p_.pending.take(key)) {
            ++p_.counters.unreachable;
            safely(p_.log, [&] { taken->responder->fail(std::move(*unreachable)); });
        }
        return;
    }
    if (expected != topic.kind) {
        ++p_.counters.unmatched;  // same @id on another kind of response: not ours
        return;
    }
    if (topic.kind == TopicKind::event_register_response || topic.kind == TopicKind::sample_register_response)
        if (p_.note_instance) p_.note_instance(topic.dev, payload);  // client_model_cache.cpp
    if (!responder->decode(payload)) {
        ++p_.counters.malformed;
        p_.log.warn("client: malformed response {} on {} ignored", key, build_topic(topic));
        return;
    }
    if (auto taken = p_.pending.take(key)) {
        ++p_.counters.responses;
        safely(p_.log, [&] { taken->responder->complete(); });
    }
}

void MessageRouter::handle_notification(const ParsedTopic& topic, const Message& m) {
    const auto subs = p_.link.matching(m.topic);
    if (subs.empty()) return;
    switch (topic.kind) {
        case TopicKind::sample:
        case TopicKind::dynamic_sample: {  // client_sampling.cpp filters by channel
            auto dtu = decode<SampleDtu>(m.payload);
            if (!dtu) {
                ++p_.counters.malformed;
                return;
            }
            if (dtu->guid.empty()) dtu->guid = topic.dev;
            if (!first_delivery(m.topic, dtu->id + "@" + std::to_string(dtu->begin_time)))
                return;  // a QoS 1 repeat (client_liveness.cpp)
            deliver_to<SampleHandler>(subs, *dtu, p_.counters.samples);
            break;
        }
        case TopicKind::notify_state: {
            if (m.payload.empty()) {  // a cleared retained state
                known_states_.erase(topic.dev);
                return;
            }
            auto dtu = decode<NotifyState>(m.payload);
            if (!dtu) {
                ++p_.counters.malformed;
                return;
            }
            if (dtu->tid.empty()) dtu->tid = topic.dev;
            known_states_[topic.dev] = dtu->state;
            deliver_to<StateHandler>(subs, *dtu, p_.counters.notifications);
            break;
        }
        case TopicKind::probe_version: {
            auto dtu = decode<ProbeVersionRequest>(m.payload);
            if (!dtu) {
                ++p_.counters.malformed;
                return;
            }
            if (dtu->guid.empty()) dtu->guid = topic.dev;
            deliver_to<VersionHandler>(subs, *dtu, p_.counters.notifications);
            break;
        }
        default: ++p_.counters.unmatched; break;
    }
}

bool MessageRouter::first_delivery(const std::string& stream, const std::string& key) {
    if (duplicates_.first(stream, key)) return true;
    ++p_.counters.duplicates;
    p_.log.debug("client: repeated DTU on {} ({}) not handed on again", stream, key);
    return false;
}

std::optional<std::string> MessageRouter::known_state(const std::string& dev) const {
    const auto it = known_states_.find(dev);
    if (it == known_states_.end()) return std::nullopt;
    return it->second;
}

}  // namespace nclink::client_detail
