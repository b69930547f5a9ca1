// The agent's terminals: registration (8.2.1/8.2.2), discovery (8.2.3/
// 8.2.4), Probe/Version and the model fetch (8.2.5-8.2.7), Notify/State
// (8.2.16).
#include "agent/agent_impl.hpp"

namespace nclink {

using namespace agent_detail;

void Agent::Impl::on_register(State& p, const Message& m, Out& out) {
    if (m.retained) {
        ++counters.retained;
        return;
    }
    auto request = decode<RegisterRequest>(m.payload);
    if (!request) {
        ++counters.malformed;
        ++counters.refused;
        // Answerable only when a usable cli_uuid can be picked out.
        const Json raw = Json::parse(m.payload, nullptr, false);
        if (raw.is_object() && raw.contains("cli_uuid") && raw["cli_uuid"].is_string()) {
            const std::string cli = raw["cli_uuid"].get<std::string>();
            if (publishable_level(cli))
                if (auto answer = make_error_reply(TopicKind::register_request, peek_message_id(m.payload), cli, request.error()))
                    reply(out, topics::register_response(cli), *answer);
        }
        log.warn("agent: malformed Register/Request: {}", request.error().describe());
        return;
    }
    const std::string& cli = request->cli_uuid;
    if (p.registrar->valid_id(cli)) {
        p.presence.set_kind(cli, p.registrar->listed_kind(cli));
        alive(p, cli, Kind::unknown, out);  // before deciding: the registration belongs to this online period
    }
    // A terminal that heard no answer within its register timeout sends the
    // same request again. While the agent's answers queue (10,000 terminals
    // starting together), answering every resend tripled the queue it was
    // waiting behind; the first answer reaches it on the same connection.
    constexpr std::chrono::seconds kResendQuiet{30};
    if (p.registrar->resent_while_answered(cli, id_text(request->msg_id), p.presence.online_periods(cli), clock->now(),
                                           kResendQuiet)) {
        ++counters.repeated;
        return;
    }
    const auto decision = p.registrar->decide(*request, p.presence, wall_s());
    RegisterResponse response;
    response.msg_id = request->msg_id;
    response.cli_uuid = cli;
    response.status = decision.status;
    if (decision.status.ok) {
        ++counters.registrations;
        p.saves.registry_changed();
        log.info("agent: registered {} {}", to_string(p.presence.kind(cli)), cli);
    } else {
        ++counters.refused;
        log.warn("agent: registration of '{}' refused ({} {}): {}", cli, response.status.error.value_or(0),
                 response.status.reason.value_or(""), decision.why);
    }
    if (!publishable_level(cli)) return;  // no topic to answer on (the id has a wildcard or is empty)
    reply(out, topics::register_response(cli), to_json(response));
    if (decision.status.ok) p.registrar->answered(cli, clock->now());
}

void Agent::Impl::on_register_response(State& p, const ParsedTopic& topic, const Message& m) {
    auto response = decode<RegisterResponse>(m.payload);
    if (!response || !response->status.ok || response->cli_uuid != topic.dev) return;
    if (!p.registrar->registered(topic.dev)) p.saves.registry_changed();
    p.registrar->record(topic.dev, p.presence.kind(topic.dev), wall_s(), p.presence.online_periods(topic.dev));
}

void Agent::Impl::on_discovery(State& p, const ParsedTopic& topic, const Message& m, Out& out) {
    if (m.retained) {
        ++counters.retained;
        return;
    }
    const std::string ex = topic.ex.value_or("");
    alive(p, ex, Kind::application, out);
    auto request = decode<DiscoveryRequest>(m.payload);
    if (!request) {
        ++counters.malformed;
        if (auto answer = make_error_reply(TopicKind::discovery_request, peek_message_id(m.payload), ex, request.error()))
            reply(out, topics::discovery_response(ex), *answer);
        return;
    }
    DiscoveryResponse response;
    response.msg_id = request->msg_id;
    response.guid = ex;
    std::vector<DeviceListEntry> list;
    const auto add = [&](const std::string& tid) {
        DeviceListEntry entry;
        entry.guid = tid;
        entry.status = to_wire(p.presence.status(tid));
        entry.last_alive_time_stamp = std::to_string(p.presence.last_alive_s(tid));
        list.push_back(std::move(entry));
    };
    for (const auto& [tid, registration] : p.registrar->all()) {
        const Kind kind = p.presence.kind(tid) != Kind::unknown ? p.presence.kind(tid) : registration.kind;
        if (kind != Kind::adapter || rights_of(config.access, ex, tid) == access_none) continue;
        add(tid);
    }
    // Online adapters the agent has not seen register: after a restart
    // without its state directory they are known from their retained
    // Notify/State and their traffic only (learn_kind(p, )).
    for (const auto& tid : p.presence.known()) {
        if (p.presence.kind(tid) != Kind::adapter || p.presence.status(tid) != Status::online) continue;
        if (p.registrar->all().count(tid) || rights_of(config.access, ex, tid) == access_none) continue;
        if (!config.registration.open && !config.registration.terminals.count(tid)) continue;  // never allowed in
        add(tid);
    }
    if (!list.empty()) response.device_list = std::move(list);  // null: no accessible adapter (table 24)
    ++counters.discoveries;
    reply(out, topics::discovery_response(ex), to_json(response));
}

void Agent::Impl::on_version(State& p, const ParsedTopic& topic, const Message& m, Out& out) {
    const std::string& dev = topic.dev;
    alive(p, dev, Kind::adapter, out);
    if (m.retained) return;  // a stale announcement replayed by the broker
    auto request = decode<ProbeVersionRequest>(m.payload);
    ProbeVersionResponse response;
    response.guid = dev;
    if (!request) {
        ++counters.malformed;
        response.msg_id = peek_message_id(m.payload);
        response.status = ResponseStatus(request.error());
        reply(out, topics::probe_version_response(dev), to_json(response));
        return;
    }
    response.msg_id = request->msg_id;
    response.status = ResponseStatus::success();
    response.version = request->version;
    ++counters.versions;
    reply(out, topics::probe_version_response(dev), to_json(response));
    if (p.models.announce(dev, request->version, clock->now())) fetch_model(p, dev, out);
}

void Agent::Impl::fetch_model(State& p, const std::string& dev, Out& out) {
    log.info("agent: fetching the model of {} (version {})", dev, p.models.find(dev)->version);
    ask_model(p, dev, "fetch", out);
}

// A Probe/Query of the agent's own (8.2.7), `what` naming it in its @id.
// Its answer is the model fetch (model_cache.hpp): a Probe/Version arriving
// meanwhile waits for it, and it fills the cache.
void Agent::Impl::ask_model(State& p, const std::string& dev, std::string_view what, Out& out) {
    ProbeQueryRequest query;
    const std::string id = p.next_id(config.agent_id, what);
    query.msg_id = Json(id);
    query.guid = dev;
    p.models.fetching(dev, id, clock->now() + config.request_timeout);
    out.push_back(Message{topics::probe_query_request(dev, config.agent_id), encode(query), 1, false});
}

// This instance asks `tid` (its share when instances split the work: every
// instance watches the answer, so one question is enough) and can.
bool Agent::Impl::asks(const std::string& tid) const {
    return (config.instances <= 1 || instance_of(tid, config.instances) == config.instance) && publishable_level(tid);
}

bool Agent::Impl::model_fetch_waits(const State& p, const std::string& tid) const {
    const auto* cached = p.models.find(tid);
    return cached && !cached->fetch_id.empty();
}

void Agent::Impl::on_version_response(State& p, const ParsedTopic& topic, const Message& m, Out&) {
    // Another agent (or an application) acknowledged a version: keep the
    // number; the model comes with that agent's fetch, which every agent sees.
    auto response = decode<ProbeVersionResponse>(m.payload);
    if (!response || !response->version || (response->status && !response->status->ok)) return;
    p.presence.set_kind(topic.dev, Kind::adapter);
    (void)p.models.announce(topic.dev, *response->version, clock->now());
}

void Agent::Impl::on_notify(State& p, const ParsedTopic& topic, const Message& m, Out& out) {
    if (m.payload.empty()) return;  // a cleared retained state
    auto notify = decode<NotifyState>(m.payload);
    if (!notify || (notify->state != "online" && notify->state != "offline")) {
        ++counters.malformed;
        return;
    }
    const std::string& tid = topic.dev;
    if (tid == config.agent_id) return;
    if (p.own_echo(tid, notify->state)) return;  // our own announcement coming back
    p.announcements.cancel(tid);                 // it (or another agent) said it: nothing to announce
    const Status status = notify->state == "online" ? Status::online : Status::offline;
    if (p.presence.set_state(tid, status, clock->now(), wall_s())) {
        p.saves.registry_changed();
        log.info("agent: {} is {}{}", tid, notify->state, m.retained ? " (retained state)" : "");
    }
    if (status == Status::offline) {
        p.kind_probes.erase(tid);
        unreachable_for(p, tid, out);
    } else if (p.presence.kind(tid) == Kind::unknown) {
        learn_kind(p, tid, out);
    }
}

// An online terminal the agent knows nothing of: typically an adapter whose
// retained Notify/State the agent finds when it starts without its state
// directory. Discovery must list it at once (8.2.3: the adapters online or
// registered), but a Notify/State does not say whether its terminal is an
// adapter or an application. A Probe/Query does: an adapter answers it
// (and the answer fills the model cache, which the agent needs for an
// offline adapter anyway); an application does not, and nothing else
// happens. Asked once per online period, by the terminal's own instance
// (asks()).
void Agent::Impl::learn_kind(State& p, const std::string& tid, Out& out) {
    if (!asks(tid) || !p.kind_probes.insert(tid).second) return;
    if (model_fetch_waits(p, tid)) return;  // it asks already
    log.debug("agent: {} is online but of unknown kind: asking it for its model", tid);
    ask_model(p, tid, "kind", out);
}

// An adapter that published nothing for adapter_liveness_ms may still be
// there: its last will can die with its broker node (a cluster), and the
// agent may simply not see its traffic (samples, unless observe_samples).
// So it is asked for its model (Probe/Query, 8.2.7: every adapter answers
// it, and the agent reads no model to pick an item) and stays online while
// the answer may come (request_timeout_ms); the answer is a DTU from it like
// any other, and it refreshes the model cache. Asked by the terminal's own
// instance (asks()).
void Agent::Impl::ask_alive(State& p, const std::string& tid, Out& out) {
    if (!asks(tid) || model_fetch_waits(p, tid)) return;
    log.debug("agent: adapter {} silent for {} ms: asking it for its model", tid, config.adapter_liveness.count());
    ask_model(p, tid, "alive", out);
}

// 8.3.5: the adapter went away while requests to it were waiting.
void Agent::Impl::unreachable_for(State& p, const std::string& dev, Out& out) {
    for (auto& request : p.pending.take_for(dev))
        answer_unreachable(request.kind, request.topic, dev, request.ex, request.msg_id, out);
}

}  // namespace nclink
