// The adapter state machine of the NC-Link state-machine text (docs/state-machines.md,
// items 64-82): initial, normal, request, disconnected. The table is data
// (src/adapter/adapter_state.cpp): one row per state and event, naming the
// next state, the actions and the item of the text it follows. The adapter
// runs exactly the actions the row names (src/adapter/adapter_link.cpp);
// docs/standard-coverage.md lists every row and where nclink refines it.
#pragma once

#include <nclink/export.hpp>

#include <cstddef>
#include <string_view>

namespace nclink {

enum class AdapterState {
    initial,       ///< before the model is loaded and the features run
    normal,        ///< connected; every response so far went out
    request,       ///< connected, but a response could not be handed to the link; it is kept to send again
    disconnected,  ///< the link to the agent/broker is down; responses are kept until it is back
};

enum class AdapterEvent {
    initialized,      ///< model loaded, driver open, features started (67)
    request_handled,  ///< a request was processed; its response is at hand (69, 74, 79)
    response_failed,  ///< the link would not take a response (69: -> request)
    link_lost,        ///< 70, 75, 80
    link_restored,    ///< 71, 76, 81
    sample_due,       ///< a sample channel's upload time came (72, 77, 82)
    model_changed,    ///< nclink: the model was replaced (Probe/Set 8.2.9 or Adapter::replace_model)
    retry_due,        ///< nclink: housekeeping tick: try the kept responses again while connected
    cache_flushed,    ///< nclink: every kept response went out
};

/// What the adapter does on a transition (a bit set).
enum AdapterAction : unsigned {
    action_none = 0,
    action_initialize = 1u << 0,        ///< model, driver, features: Adapter::start() has done it when it fires `initialized`
    action_send_response = 1u << 1,     ///< publish the response DTU
    action_cache_response = 1u << 2,    ///< keep the response (bounded) to send when the link takes it
    action_flush_cached = 1u << 3,      ///< publish the kept responses, in order
    action_send_sample = 1u << 4,       ///< publish the Sample DTU (the sample path spools it while offline)
    action_announce_online = 1u << 5,   ///< retained Notify/State online (8.2.16)
    action_register = 1u << 6,          ///< Register/Request (8.2.1; again on every connection, 8.3.6)
    action_announce_version = 1u << 7,  ///< Probe/Version (8.2.5: at start and when the model changes)
};

struct NCLINK_API AdapterTransition {
    AdapterState next;
    unsigned actions;
};

/// One row of the table.
struct NCLINK_API AdapterTableRow {
    AdapterState state;
    AdapterEvent event;
    AdapterState next;
    unsigned actions;
    const char* source;  ///< the item of the state-machine text (or the clause) the row follows, "nclink" for additions
};

/// The whole table: every state x event pair exactly once. Pure data.
struct NCLINK_API AdapterTable {
    const AdapterTableRow* rows;
    std::size_t size;
};
NCLINK_API AdapterTable adapter_table() noexcept;

/// The row of `state` x `event`. Pure and thread-safe.
NCLINK_API AdapterTransition adapter_transition(AdapterState state, AdapterEvent event) noexcept;

inline constexpr std::size_t adapter_state_count = 4;
inline constexpr std::size_t adapter_event_count = 9;

NCLINK_API std::string_view to_string(AdapterState state) noexcept;
NCLINK_API std::string_view to_string(AdapterEvent event) noexcept;

}  // namespace nclink
