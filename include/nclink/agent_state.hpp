// The agent state machine of the NC-Link state-machine text (docs/state-machines.md, items
// 28-63): initial, normal, application down, adapter down, both down. The
// agent keeps one such state for every pair of an application and an
// adapter that talk through it, derived from who is online (8.2.16); the
// table (src/agent/agent_state.cpp) decides what the agent does with a
// request, a response or a sample of the pair. docs/standard-coverage.md
// lists every row and where nclink refines it.
#pragma once

#include <nclink/export.hpp>

#include <cstddef>
#include <string_view>

namespace nclink {

enum class AgentState {
    initial,           ///< before the agent serves (31)
    normal,            ///< application and adapter online
    application_down,  ///< the application's link is down, the adapter's up
    adapter_down,      ///< the adapter's link is down, the application's up
    both_down,         ///< neither is reachable ("complete interruption")
};

enum class AgentEvent {
    initialized,           ///< the agent has read its state and serves (31)
    request_received,      ///< a request DTU of the pair (33, 41, 49, 57)
    response_received,     ///< a response DTU of the pair (34, 42, 50, 58)
    application_lost,      ///< 35, 43, 51, 59
    application_restored,  ///< 36, 44, 52, 60
    adapter_lost,          ///< 37, 45, 53, 61
    adapter_restored,      ///< 38, 46, 54, 62
    sample_received,       ///< 39, 47, 55, 63
};

/// What the agent does on a transition (a bit set).
enum AgentAction : unsigned {
    agent_action_none = 0,
    agent_action_check_registrations = 1u << 0,  ///< read the registry (31): Agent::start() does it
    agent_action_forward_request = 1u << 1,      ///< the broker carries it; the agent watches for the answer (203)
    agent_action_forward_response = 1u << 2,     ///< the broker carries it; the agent notes the adapter alive
    agent_action_hold_request =
        1u << 3,  ///< the adapter cannot get it: answered in its place (DEV_UNREACHABLE 8.3.4, or the cached model)
    agent_action_hold_response = 1u << 4,   ///< the application cannot get it now: its session keeps it (QoS 1)
    agent_action_forward_sample = 1u << 5,  ///< the broker carries it to the subscribers
    agent_action_hold_sample = 1u << 6,     ///< the application's session keeps it (QoS 1 samples) until it is back
};

struct NCLINK_API AgentTransition {
    AgentState next;
    unsigned actions;
};

struct NCLINK_API AgentTableRow {
    AgentState state;
    AgentEvent event;
    AgentState next;
    unsigned actions;
    const char* source;  ///< the item of the state-machine text the row follows, or why nclink differs
};

struct NCLINK_API AgentTable {
    const AgentTableRow* rows;
    std::size_t size;
};
/// Every state x event pair exactly once. Pure data.
NCLINK_API AgentTable agent_table() noexcept;
NCLINK_API AgentTransition agent_transition(AgentState state, AgentEvent event) noexcept;

/// The state of a pair from who is online (after initialization).
NCLINK_API AgentState agent_state_of(bool application_online, bool adapter_online) noexcept;

inline constexpr std::size_t agent_state_count = 5;
inline constexpr std::size_t agent_event_count = 8;

NCLINK_API std::string_view to_string(AgentState state) noexcept;
NCLINK_API std::string_view to_string(AgentEvent event) noexcept;

}  // namespace nclink
