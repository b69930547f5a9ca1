// The agent state machine as data: state-machine text items 30-63, one row per state
// and event. In nclink the broker carries every DTU; the agent decides what
// happens to a request whose adapter is unreachable and watches the rest.
#include <nclink/agent_state.hpp>

namespace nclink {
namespace {

using S = AgentState;
using E = AgentEvent;

// 41/49/57 say "cache the request". 8.3.4/8.3.5 let the agent drop it if it
// tells the application the adapter is unreachable: nclink answers at once
// (DEV_UNREACHABLE, or the cached model for Probe/Query), so no application
// waits on a request the adapter may never see.
constexpr unsigned kHoldRequest = agent_action_hold_request;

constexpr AgentTableRow kTable[] = {
    // ---- initial (30-31)
    {S::initial, E::initialized, S::normal, agent_action_check_registrations, "31"},
    {S::initial, E::request_received, S::initial, agent_action_none, "cannot happen: nothing is subscribed before initialization"},
    {S::initial, E::response_received, S::initial, agent_action_none,
     "cannot happen: nothing is subscribed before initialization"},
    {S::initial, E::application_lost, S::initial, agent_action_none, "cannot happen: nothing is subscribed before initialization"},
    {S::initial, E::application_restored, S::initial, agent_action_none,
     "cannot happen: nothing is subscribed before initialization"},
    {S::initial, E::adapter_lost, S::initial, agent_action_none, "cannot happen: nothing is subscribed before initialization"},
    {S::initial, E::adapter_restored, S::initial, agent_action_none, "cannot happen: nothing is subscribed before initialization"},
    {S::initial, E::sample_received, S::initial, agent_action_none, "cannot happen: nothing is subscribed before initialization"},
    // ---- normal (32-39)
    {S::normal, E::initialized, S::normal, agent_action_none, "nclink: initialization happens once"},
    {S::normal, E::request_received, S::normal, agent_action_forward_request, "33"},
    {S::normal, E::response_received, S::normal, agent_action_forward_response, "34"},
    {S::normal, E::application_lost, S::application_down, agent_action_none, "35"},
    {S::normal, E::application_restored, S::normal, agent_action_none, "36"},
    {S::normal, E::adapter_lost, S::adapter_down, agent_action_none, "37"},
    {S::normal, E::adapter_restored, S::normal, agent_action_none, "38"},
    {S::normal, E::sample_received, S::normal, agent_action_forward_sample, "39"},
    // ---- application down (40-47)
    {S::application_down, E::initialized, S::application_down, agent_action_none, "nclink: initialization happens once"},
    // A request of the pair comes from its application: it is a sign of life
    // (3.22) that ends this state before the row is taken.
    {S::application_down, E::request_received, S::application_down, agent_action_forward_request,
     "41; nclink: the request shows the application is back"},
    {S::application_down, E::response_received, S::application_down, agent_action_hold_response, "42"},
    {S::application_down, E::application_lost, S::application_down, agent_action_none, "43"},
    {S::application_down, E::application_restored, S::normal, agent_action_none, "44"},
    {S::application_down, E::adapter_lost, S::both_down, agent_action_none, "45"},
    {S::application_down, E::adapter_restored, S::application_down, agent_action_none, "46"},
    {S::application_down, E::sample_received, S::application_down, agent_action_hold_sample, "47"},
    // ---- adapter down (48-55)
    {S::adapter_down, E::initialized, S::adapter_down, agent_action_none, "nclink: initialization happens once"},
    {S::adapter_down, E::request_received, S::adapter_down, kHoldRequest, "49; 8.3.4 (answered DEV_UNREACHABLE)"},
    // A response of the pair comes from its adapter: a sign of life that
    // ends this state before the row is taken.
    {S::adapter_down, E::response_received, S::adapter_down, agent_action_forward_response,
     "50; nclink: the response shows the adapter is back"},
    {S::adapter_down, E::application_lost, S::both_down, agent_action_none, "51"},
    {S::adapter_down, E::application_restored, S::adapter_down, agent_action_none, "52"},
    {S::adapter_down, E::adapter_lost, S::both_down, agent_action_none,
     "53 (the text names the complete interruption; the adapter was down already)"},
    {S::adapter_down, E::adapter_restored, S::normal, agent_action_none, "54"},
    {S::adapter_down, E::sample_received, S::adapter_down, agent_action_forward_sample, "55"},
    // ---- both down (56-63)
    {S::both_down, E::initialized, S::both_down, agent_action_none, "nclink: initialization happens once"},
    {S::both_down, E::request_received, S::both_down, kHoldRequest, "57; 8.3.4"},
    {S::both_down, E::response_received, S::both_down, agent_action_hold_response, "58"},
    {S::both_down, E::application_lost, S::both_down, agent_action_none, "59"},
    {S::both_down, E::application_restored, S::adapter_down, agent_action_none, "60"},
    {S::both_down, E::adapter_lost, S::both_down, agent_action_none, "61"},
    {S::both_down, E::adapter_restored, S::application_down, agent_action_none, "62"},
    {S::both_down, E::sample_received, S::both_down, agent_action_forward_sample, "63"},
};

static_assert(sizeof kTable / sizeof kTable[0] == agent_state_count * agent_event_count, "one row per state and event");

}  // namespace

AgentTable agent_table() noexcept { return {kTable, sizeof kTable / sizeof kTable[0]}; }

AgentTransition agent_transition(AgentState state, AgentEvent event) noexcept {
    for (const auto& row : kTable)
        if (row.state == state && row.event == event) return {row.next, row.actions};
    return {state, agent_action_none};
}

AgentState agent_state_of(bool application_online, bool adapter_online) noexcept {
    if (application_online) return adapter_online ? S::normal : S::adapter_down;
    return adapter_online ? S::application_down : S::both_down;
}

std::string_view to_string(AgentState state) noexcept {
    switch (state) {
        case S::initial: return "initial";
        case S::normal: return "normal";
        case S::application_down: return "application_down";
        case S::adapter_down: return "adapter_down";
        case S::both_down: return "both_down";
    }
    return "?";
}

std::string_view to_string(AgentEvent event) noexcept {
    switch (event) {
        case E::initialized: return "initialized";
        case E::request_received: return "request_received";
        case E::response_received: return "response_received";
        case E::application_lost: return "application_lost";
        case E::application_restored: return "application_restored";
        case E::adapter_lost: return "adapter_lost";
        case E::adapter_restored: return "adapter_restored";
        case E::sample_received: return "sample_received";
    }
    return "?";
}

}  // namespace nclink
