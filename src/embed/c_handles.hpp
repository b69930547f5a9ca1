// The objects behind the opaque handles of nclink.h.
#pragma once

#include <nclink/adapter.hpp>
#include <nclink/nclink.h>
#include <nclink/sampling.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

struct nclink_adapter {
    std::unique_ptr<nclink::Adapter> adapter;
};

/// A push channel as the firmware holds it. A model change (Probe/Set,
/// replace_model) replans the sample channels and retires the PushChannel
/// taken before; the adapter's model listener then takes the new one into
/// `handoff`, and the pushing thread swaps it in at its next push without
/// waiting (a try-lock) and without allocating or freeing (the retired
/// channel goes back into `handoff`, freed off the real-time thread).
struct nclink_channel {
    struct Handoff {
        std::mutex mutex;  ///< guards channel and row
        nclink::PushChannel channel;
        std::vector<nclink::SampleValue> row;
        std::atomic<bool> ready{false};  ///< channel is a new one to swap in
    };
    nclink::PushChannel channel;
    /// One row of SampleValues, sized for `channel` so a push never allocates.
    std::vector<nclink::SampleValue> row;
    std::shared_ptr<Handoff> handoff = std::make_shared<Handoff>();
};
