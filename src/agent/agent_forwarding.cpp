// Requests to adapters seen by the agent: refused with 301 by the ACL,
// answered DEV_UNREACHABLE (8.3.4) for an offline adapter, answered from the
// cached model for Probe/Query, and 203 when an adapter stays silent.
#include "agent/agent_impl.hpp"

namespace nclink {

using namespace agent_detail;

void Agent::Impl::on_request(State& p, const ParsedTopic& topic, const Message& m, Out& out) {
    if (m.retained) {
        ++counters.retained;
        return;  // docs/wire.md: never act on a replayed (retained) request
    }
    if (topic.ex && *topic.ex == config.agent_id) return;  // our own model fetch
    if (topic.ex) alive(p, *topic.ex, Kind::application, out);
    const std::string& dev = topic.dev;
    const std::string ex = topic.ex.value_or("");
    const MessageId msg_id = peek_message_id(m.payload);
    // With a closed allowlist registration is required (8.2.1): a terminal
    // that did not register is refused as one without the right.
    const bool unregistered = !config.registration.open && !p.registrar->registered(ex);
    if (unregistered || !allowed(config.access, ex, dev, *required_right(topic.kind))) {
        ++counters.denied;
        log.info("agent: {} from '{}' to {} denied (301{})", to_string(topic.kind), ex, dev,
                 unregistered ? ", not registered" : "");
        if (auto answer =
                make_error_reply(topic.kind, msg_id, dev,
                                 make_error(ErrorCode::permission_denied, unregistered ? "not registered" : "access control")))
            reply_all(out, topic, marked(*answer));
        return;
    }
    const AgentState pair = p.pair_state(topic.ex, dev);
    const auto row = agent_transition(pair, AgentEvent::request_received);
    if (row.actions & agent_action_hold_request) {
        log.debug("agent: {} -> {} is {}: {} answered in the adapter's place", ex, dev, to_string(pair), to_string(topic.kind));
        const CachedModel* cached = p.models.find(dev);
        if (topic.kind == TopicKind::probe_query_request && cached && cached->model) {
            ProbeQueryResponse response;
            response.msg_id = msg_id;
            response.guid = dev;
            response.probe = *cached->model;
            response.private_info =
                Json{{"cached", true}, {"version", cached->model_version}, {"fetchedAt", std::to_string(cached->fetched_at_s)}};
            ++counters.cached;
            reply_all(out, topic, marked(to_json(response)));
            return;
        }
        answer_unreachable(topic.kind, m.topic, dev, topic.ex, msg_id, out);
        return;
    }
    if (!(row.actions & agent_action_forward_request)) return;  // before initialization: not ours yet
    Forwarded request;
    request.kind = topic.kind;
    request.dev = dev;
    request.ex = topic.ex;
    request.msg_id = msg_id;
    request.topic = m.topic;
    request.deadline = clock->now() + config.request_timeout;
    p.pending.add(std::move(request));
}

void Agent::Impl::on_response(State& p, const ParsedTopic& topic, const Message& m, Out& out) {
    if (m.retained || from_agent(m.payload)) return;  // an agent's answer says nothing about the adapter
    const std::string id = id_text(peek_message_id(m.payload));
    if (topic.kind == TopicKind::probe_query_response) {
        // Our fetch's answer, or any application's: either refreshes the cache.
        auto response = decode<ProbeQueryResponse>(m.payload);
        if (response && response->status.ok && response->probe && response->probe->is_object()) {
            if (p.models.store(topic.dev, std::move(*response->probe), wall_s())) {
                ++counters.fetched;
                p.saves.model_changed(topic.dev);
                log.info("agent: cached the model of {} (version {})", topic.dev, p.models.find(topic.dev)->version);
            }
        } else if (topic.ex && *topic.ex == config.agent_id && p.models.is_fetch(topic.dev, id)) {
            log.warn("agent: fetching the model of {} failed", topic.dev);
            p.models.fetching(topic.dev, "", clock->now());
        }
    }
    alive(p, topic.dev, Kind::adapter, out);
    const AgentState pair = p.pair_state(topic.ex, topic.dev);
    if (agent_transition(pair, AgentEvent::response_received).actions & agent_action_hold_response) {
        // The broker keeps it in the application's session (QoS 1) until it
        // is back (the state-machine text 42, 58; 8.3.2): counted, nothing to send now.
        ++counters.held;
        log.debug("agent: {} -> {} is {}: {} held for the application", topic.ex.value_or(""), topic.dev, to_string(pair),
                  to_string(topic.kind));
    }
    if (!id.empty()) (void)p.pending.answered(topic.kind, topic.dev, topic.ex, id);
}

bool Agent::Impl::from_agent(const std::string& payload) {
    if (payload.find("\"agent\"") == std::string::npos) return false;  // cheap filter: this runs per response
    const Json dtu = Json::parse(payload, nullptr, false);
    if (!dtu.is_object()) return false;
    const auto info = dtu.find("privateInfo");
    return info != dtu.end() && info->is_object() && info->contains("agent");
}

}  // namespace nclink
