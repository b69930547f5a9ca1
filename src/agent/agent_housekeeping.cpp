// The agent's housekeeping thread: request timeouts, terminal liveness on
// the injected clock, and the state files.
#include "agent/agent_impl.hpp"

namespace nclink {

using namespace agent_detail;

// Thread: housekeeping. Polls the injected clock every tick.
void Agent::Impl::housekeep() {
    auto last_save = clock->now();
    std::unique_lock<std::mutex> lock(hk_mutex);
    while (!hk_stopping) {
        lock.unlock();
        Out out;
        {
            std::lock_guard<std::mutex> state(mutex);
            tick(out);
        }
        publish(out);
        if (clock->now() - last_save >= std::chrono::seconds(1)) {
            persist(false);
            last_save = clock->now();
        }
        lock.lock();
        hk_wake.wait_for(lock, config.tick, [this] { return hk_stopping; });
    }
}

void Agent::Impl::tick(Out& out) {
    const auto now = clock->now();
    for (auto& request : pending.take_expired(now)) {
        ++counters.timeouts;
        log.info("agent: {} to {} not answered within {} ms: 203", to_string(request.kind), request.dev,
                 config.request_timeout.count());
        if (auto answer = make_error_reply(request.kind, request.msg_id, request.dev,
                                           make_error(ErrorCode::timeout, "no answer from the adapter")))
            for (auto& t : response_topics(request.topic, true)) reply(out, std::move(t), marked(*answer));
    }
    for (const auto& tid : presence.expire(now)) {
        log.info("agent: {} {} is offline (no DTU for its liveness time)", to_string(presence.kind(tid)), tid);
        announce_state(tid, Status::offline, out);
        registry_dirty = true;
        unreachable_for(tid, out);
    }
    models.expire_fetches(now);
}

// Writes what changed; the text is built under the lock, written outside it.
void Agent::Impl::persist(bool all) {
    if (!store.enabled()) return;
    std::optional<std::pair<Registrar, Presence>> registry;
    std::vector<std::pair<std::string, CachedModel>> dirty_models;
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (!loaded) return;  // never overwrite a file that could not be read
        if (registry_dirty || all) registry.emplace(*registrar, presence);
        registry_dirty = false;
        for (const auto& dev : models_dirty)
            if (const auto* entry = models.find(dev)) dirty_models.emplace_back(dev, *entry);
        models_dirty.clear();
    }
    if (registry)
        if (auto r = store.save_registry(registry->first, registry->second); !r)
            log.error("agent: cannot save the registry: {}", r.error().describe());
    for (const auto& [dev, entry] : dirty_models)
        if (auto r = store.save_model(dev, entry); !r)
            log.error("agent: cannot save the model of {}: {}", dev, r.error().describe());
}

}  // namespace nclink
