// What of the agent's picture has changed since the state files were last
// written (state_store.hpp): the registry, and the models of which devices.
// Guarded by the agent's picture lock like the picture itself; the
// housekeeping thread takes the changes and writes them outside the lock.
#pragma once

#include <set>
#include <string>

namespace nclink::agent_detail {

class PendingSaves {
public:
    /// The state files were read: only from now may they be written (a file
    /// that could not be read is never overwritten).
    void loaded() { loaded_ = true; }
    void registry_changed() { registry_ = true; }
    void model_changed(const std::string& dev) { models_.insert(dev); }

    struct Batch {
        bool registry = false;
        std::set<std::string> models;
    };
    /// Takes what changed (the registry as well when `all`); nothing before loaded().
    Batch take(bool all) {
        Batch batch;
        if (!loaded_) return batch;
        batch.registry = registry_ || all;
        batch.models.swap(models_);
        registry_ = false;
        return batch;
    }

private:
    bool loaded_ = false;
    bool registry_ = false;
    std::set<std::string> models_;
};

}  // namespace nclink::agent_detail
