// The adapter state machine of the NC-Link state-machine patent text
// (the adapter state machine, docs/state-machines.md): initial, normal, request, disconnected.
#pragma once

#include <nclink/export.hpp>
#include <string_view>

namespace nclink {

enum class AdapterState {
    initial,       ///< before the model is loaded and the adapter registered
    normal,        ///< connected; every response so far went out
    request,       ///< connected, but a response could not be handed to the link ("request state")
    disconnected,  ///< the link to the agent/broker is down; responses are cached
};

enum class AdapterEvent {
    initialized,           ///< model loaded, registration sent
    request_answered,      ///< a request was handled and its response handed to the link
    request_answer_failed, ///< a request was handled but its response could not be handed over
    link_lost,
    link_restored,
    sample_due,            ///< a sample channel's upload time came
};

/// What the adapter does on a transition (a bit set).
enum AdapterAction : unsigned {
    action_none = 0,
    action_initialize = 1u << 0,       ///< load the model, register with the agent
    action_send_response = 1u << 1,    ///< publish the response DTU
    action_cache_response = 1u << 2,   ///< keep the response for later
    action_flush_cached = 1u << 3,     ///< publish cached responses
    action_send_sample = 1u << 4,      ///< publish the Sample DTU (buffered while disconnected)
};

struct NCLINK_API AdapterTransition {
    AdapterState next;
    unsigned actions;
};

/// The transition table, item by item of the adapter state machine (docs/state-machines.md). Pure and thread-safe.
NCLINK_API AdapterTransition adapter_transition(AdapterState state, AdapterEvent event) noexcept;

NCLINK_API std::string_view to_string(AdapterState state) noexcept;
NCLINK_API std::string_view to_string(AdapterEvent event) noexcept;

}  // namespace nclink
