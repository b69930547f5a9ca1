// What the engine's pieces (SamplingEngine, Scheduler, Uploader) share: the
// dependencies, the channel list and the model snapshot. The list is
// copy-on-read: the threads keep local copies and refresh them when
// `version` changes, so the hot loops take the mutex only after a change.
#pragma once

#include "sampling/channel_core.hpp"
#include "sampling/sampling_engine.hpp"

#include <atomic>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

namespace nclink::sampling_detail {

struct EngineShared {
    explicit EngineShared(EngineDeps d) : deps(std::move(d)) {
        policy = deps.config.full_policy == "block" ? FullPolicy::block : FullPolicy::drop_oldest;
        if (deps.model) model = deps.model();
    }

    EngineDeps deps;
    FullPolicy policy = FullPolicy::drop_oldest;

    mutable std::mutex mutex;
    /// Every channel, also removed ones until the uploader published their last rows.
    std::vector<std::shared_ptr<ChannelCore>> channels;
    std::shared_ptr<const feature_detail::ModelState> model;
    bool sampler_running = false;  ///< the sampling thread runs (it then sets producer_done)
    RealtimeStatus realtime;

    std::atomic<std::uint64_t> version{1};        ///< bumped on every change of `channels`
    std::atomic<std::uint64_t> model_version{1};  ///< bumped by set_model()

    std::shared_ptr<const feature_detail::ModelState> current_model() const {
        std::lock_guard<std::mutex> lock(mutex);
        return model;
    }

    /// The items the running channels read (for the sample tap). Caller holds `mutex`.
    std::set<std::string> sampled_ids_locked() const {
        std::set<std::string> ids;
        for (const auto& c : channels)
            if (!c->removed.load())
                for (const auto& point : c->spec().points) ids.insert(point.id);
        return ids;
    }
    void publish_sampled_locked() const {
        if (deps.tap) deps.tap->set_sampled(sampled_ids_locked());
    }
};

}  // namespace nclink::sampling_detail
