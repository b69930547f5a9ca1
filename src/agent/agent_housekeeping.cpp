// The agent's housekeeping thread: request timeouts, terminal liveness on
// the injected clock, and the state files.
#include "agent/agent_impl.hpp"

namespace nclink {

using namespace agent_detail;

void Agent::Impl::housekeep() {
    Out out;
    picture.with([&](State& p) { tick(p, out); });
    publish(out);
    if (clock->now() - last_save >= std::chrono::seconds(1)) {
        persist(false);
        last_save = clock->now();
    }
}

void Agent::Impl::tick(State& p, Out& out) {
    const auto now = clock->now();
    for (auto& request : p.pending.take_expired(now)) {
        ++counters.timeouts;
        log.info("agent: {} to {} not answered within {} ms: 203", to_string(request.kind), request.dev,
                 config.request_timeout.count());
        if (auto answer = make_error_reply(request.kind, request.msg_id, request.dev,
                                           make_error(ErrorCode::timeout, "no answer from the adapter")))
            for (auto& t : response_topics(request.topic, true)) reply(out, std::move(t), marked(*answer));
    }
    for (const auto& tid : p.presence.questions(now)) ask_alive(p, tid, out);
    for (const auto& tid : p.presence.expire(now)) {
        log.info("agent: {} {} is offline (no DTU for its liveness time)", to_string(p.presence.kind(tid)), tid);
        announce_state(p, tid, Status::offline, out);
        p.announcements.cancel(tid);
        p.saves.registry_changed();
        unreachable_for(p, tid, out);
    }
    p.models.expire_fetches(now);
    for (const auto& tid : p.announcements.take_due(now))
        if (p.presence.status(tid) == Status::online) announce_state(p, tid, Status::online, out);
}

// Writes what changed; the text is built under the lock, written outside it.
void Agent::Impl::persist(bool all) {
    if (!store.enabled()) return;
    std::optional<std::pair<Registrar, Presence>> registry;
    std::vector<std::pair<std::string, CachedModel>> dirty_models;
    picture.with([&](State& p) {
        auto batch = p.saves.take(all);  // nothing before the files were read
        if (batch.registry) registry.emplace(*p.registrar, p.presence);
        for (const auto& dev : batch.models)
            if (const auto* entry = p.models.find(dev)) dirty_models.emplace_back(dev, *entry);
    });
    if (registry)
        if (auto r = store.save_registry(registry->first, registry->second); !r)
            log.error("agent: cannot save the registry: {}", r.error().describe());
    for (const auto& [dev, entry] : dirty_models)
        if (auto r = store.save_model(dev, entry); !r)
            log.error("agent: cannot save the model of {}: {}", dev, r.error().describe());
}

}  // namespace nclink
