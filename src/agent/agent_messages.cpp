// Every DTU the agent receives: routed to its handler inside the picture's
// lock (Picture::with), the replies it produces published after it.
#include "agent/agent_impl.hpp"

namespace nclink {

namespace agent_detail {

bool publishable_level(std::string_view level) {
    if (level.empty()) return false;
    for (char c : level)
        if (c == '+' || c == '#' || c == '\0') return false;
    return true;
}

bool is_response(TopicKind kind) {
    switch (kind) {
        case TopicKind::probe_query_response:
        case TopicKind::probe_set_response:
        case TopicKind::query_response:
        case TopicKind::set_response:
        case TopicKind::sample_register_response:
        case TopicKind::sample_unregister_response:
        case TopicKind::method_status:
        case TopicKind::method_result:
        case TopicKind::method_control_response:
        case TopicKind::event_register_response:
        case TopicKind::event_unregister_response: return true;
        default: return false;
    }
}

}  // namespace agent_detail

using namespace agent_detail;

// Thread: transport callback.
void Agent::Impl::on_message(const Message& m) {
    const auto parsed = parse_topic(m.topic);
    if (!parsed) return;  // not NC-Link
    Out out;
    picture.with([&](State& p) {
        try {
            dispatch(p, *parsed, m, out);
        } catch (const std::exception& e) {  // a bug must not kill the callback thread
            log.error("agent: handling {} failed: {}", m.topic, e.what());
        }
    });
    publish(out);
}

void Agent::Impl::publish(Out& out) {
    for (auto& message : out) {
        // A Discovery answer leaves on the link its request came by (start_discovery_link()).
        const bool discovery = discovery_transport && topic_kind(message.topic) == TopicKind::discovery_response;
        Transport& link = discovery ? *discovery_transport : *transport;
        if (auto r = link.publish(std::move(message)); !r) log.warn("agent: publish failed: {}", r.error().describe());
    }
}

void Agent::Impl::dispatch(State& p, const ParsedTopic& topic, const Message& m, Out& out) {
    if (!answers_here(topic, m)) return watch_request(p, topic, m, out);
    switch (topic.kind) {
        case TopicKind::register_request: return on_register(p, m, out);
        case TopicKind::register_response: return on_register_response(p, topic, m);
        case TopicKind::discovery_request: return on_discovery(p, topic, m, out);
        case TopicKind::probe_version: return on_version(p, topic, m, out);
        case TopicKind::probe_version_response: return on_version_response(p, topic, m, out);
        case TopicKind::notify_state: return on_notify(p, topic, m, out);
        case TopicKind::sample:
        case TopicKind::dynamic_sample: return alive(p, topic.dev, Kind::adapter, out, Arrival::may_overtake);
        case TopicKind::event: return alive(p, topic.dev, Kind::adapter, out);
        default: break;
    }
    if (required_right(topic.kind)) return on_request(p, topic, m, out);
    if (is_response(topic.kind)) return on_response(p, topic, m, out);
}

void Agent::Impl::reply(Out& out, std::string topic, const Json& payload) {
    out.push_back(Message{std::move(topic), payload.dump(-1, ' ', false, Json::error_handler_t::replace), 1, false});
}

// Answers the agent gives in an adapter's place carry privateInfo.agent,
// so every agent instance can tell them from the adapter's own.
Json Agent::Impl::marked(Json answer) const {
    if (!answer.contains("privateInfo") || !answer["privateInfo"].is_object()) answer["privateInfo"] = Json::object();
    answer["privateInfo"]["agent"] = config.agent_id;
    return answer;
}

void Agent::Impl::reply_all(Out& out, const ParsedTopic& request, const Json& payload) {
    for (auto& t : response_topics(request, true)) reply(out, std::move(t), payload);
}

void Agent::Impl::announce_state(State& p, const std::string& tid, Status status, Out& out) {
    ++counters.notifications;
    out.push_back(p.announce(tid, status));
}

// A DTU from `tid`: a sign of life (3.22/3.23). One that may have
// overtaken the terminal's own Notify/State (a Sample DTU, taken at QoS 0)
// makes it online in the picture at once, but its announcement waits
// kAnnounceGrace and is dropped when any Notify/State of it comes first
// (pending_announcements.hpp). 30 s: a 10,000-machine start keeps QoS 1
// messages to the agent waiting that long (docs/performance.md), and an
// adapter that states its presence itself needs no announcement at all.
void Agent::Impl::alive(State& p, const std::string& tid, Kind kind, Out& out, Arrival arrival) {
    constexpr std::chrono::seconds kAnnounceGrace{30};
    if (tid.empty() || tid == config.agent_id) return;
    if (!p.saw(tid, kind, clock->now(), wall_s())) return;
    if (arrival == Arrival::may_overtake) {
        log.info("agent: {} {} is online (it sent a DTU); announced in {} s unless it says so", to_string(p.presence.kind(tid)),
                 tid, kAnnounceGrace.count());
        p.announcements.hold(tid, clock->now(), kAnnounceGrace);
        return;
    }
    log.info("agent: {} {} is online (it sent a DTU)", to_string(p.presence.kind(tid)), tid);
    announce_state(p, tid, Status::online, out);
}

}  // namespace nclink
