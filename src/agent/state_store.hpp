// The agent's persisted state in `state_dir`: registry.json (registered
// terminals with kind and last-alive time) and models/<hex of dev>.json (the
// cached model of each adapter). Files are replaced atomically.
#pragma once

#include "agent/model_cache.hpp"
#include "agent/presence.hpp"
#include "agent/registrar.hpp"

#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <string>

namespace nclink::agent_detail {

class StateStore {
public:
    explicit StateStore(std::string dir) : dir_(std::move(dir)) {}
    bool enabled() const { return !dir_.empty(); }

    /// Reads what a previous run saved. A missing directory or file is an
    /// empty state; an unreadable registry.json is an error (412); an
    /// unreadable model file is skipped with a warning.
    Result<void> load(Registrar& registrar, Presence& presence, ModelCache& models, const Logger& log) const;
    Result<void> save_registry(const Registrar& registrar, const Presence& presence) const;
    Result<void> save_model(const std::string& dev, const CachedModel& entry) const;

    std::string registry_path() const;
    std::string model_path(const std::string& dev) const;

private:
    std::string dir_;
};

}  // namespace nclink::agent_detail
