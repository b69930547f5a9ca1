// The adapter state machine as data: state-machine text items 64-82, one row per state
// and event. Rows the text has no item for say why they exist ("nclink", or
// "cannot happen" where the adapter's start order rules the event out).
// docs/standard-coverage.md lists each row.
#include <nclink/adapter_state.hpp>

namespace nclink {
namespace {

using S = AdapterState;
using E = AdapterEvent;

// Announcing the terminal on a connection: its retained online state, a
// registration (again on every connection: 8.3.6 asks the adapter to
// register again when the links come back) and its model version (8.2.5:
// "when the adapter restarts or changes the model file").
constexpr unsigned kAnnounce = action_announce_online | action_register | action_announce_version;

constexpr AdapterTableRow kTable[] = {
    // ---- initial (item 66-67)
    {S::initial, E::initialized, S::normal, action_initialize, "67"},
    {S::initial, E::request_handled, S::initial, action_none, "cannot happen: requests are subscribed after initialization"},
    {S::initial, E::response_failed, S::initial, action_none, "cannot happen: no response before initialization"},
    {S::initial, E::link_lost, S::initial, action_none, "cannot happen: the link starts after initialization"},
    {S::initial, E::link_restored, S::initial, action_none, "cannot happen: the link starts after initialization"},
    {S::initial, E::sample_due, S::initial, action_none, "cannot happen: sampling starts with initialization"},
    {S::initial, E::model_changed, S::initial, action_none, "cannot happen: a model change before start is refused (202)"},
    {S::initial, E::retry_due, S::initial, action_none, "cannot happen: housekeeping starts after initialization"},
    {S::initial, E::cache_flushed, S::initial, action_none, "cannot happen: nothing is kept before initialization"},
    // ---- normal (items 68-72)
    {S::normal, E::initialized, S::normal, action_none, "nclink: initialization happens once"},
    {S::normal, E::request_handled, S::normal, action_send_response, "69"},
    {S::normal, E::response_failed, S::request, action_cache_response, "69 (the response is kept to send again)"},
    {S::normal, E::link_lost, S::disconnected, action_none, "70"},
    {S::normal, E::link_restored, S::normal, kAnnounce, "71; 8.3.6, 8.2.5, 8.2.16"},
    {S::normal, E::sample_due, S::normal, action_send_sample, "72"},
    {S::normal, E::model_changed, S::normal, action_announce_version, "nclink; 8.2.5, 8.2.9.3"},
    {S::normal, E::retry_due, S::normal, action_none, "nclink: nothing is kept"},
    {S::normal, E::cache_flushed, S::normal, action_none, "nclink"},
    // ---- request (items 73-77)
    {S::request, E::initialized, S::request, action_none, "nclink: initialization happens once"},
    {S::request, E::request_handled, S::request, action_send_response, "74"},
    {S::request, E::response_failed, S::request, action_cache_response, "74 (the response is kept to send again)"},
    // 75 says "cache the response": the responses that failed are kept
    // already and stay kept; nothing else is at hand.
    {S::request, E::link_lost, S::disconnected, action_none, "75"},
    {S::request, E::link_restored, S::normal, kAnnounce | action_flush_cached, "76; 8.3.6"},
    {S::request, E::sample_due, S::request, action_send_sample, "77"},
    {S::request, E::model_changed, S::request, action_announce_version, "nclink; 8.2.5, 8.2.9.3"},
    // The text leaves the request state only on a reconnection (76); a link
    // that stays up but refused one response is tried again each tick.
    {S::request, E::retry_due, S::request, action_flush_cached, "nclink"},
    {S::request, E::cache_flushed, S::normal, action_none, "nclink"},
    // ---- disconnected (items 78-82)
    {S::disconnected, E::initialized, S::disconnected, action_none, "nclink: initialization happens once"},
    {S::disconnected, E::request_handled, S::disconnected, action_cache_response, "79"},
    {S::disconnected, E::response_failed, S::disconnected, action_cache_response, "79"},
    {S::disconnected, E::link_lost, S::disconnected, action_none, "80"},
    {S::disconnected, E::link_restored, S::normal, kAnnounce | action_flush_cached, "81; 8.3.6"},
    {S::disconnected, E::sample_due, S::disconnected, action_send_sample, "82 (the sample path spools while offline)"},
    // Announced by link_restored (81) with whatever model is current then.
    {S::disconnected, E::model_changed, S::disconnected, action_none, "nclink; announced on reconnection"},
    {S::disconnected, E::retry_due, S::disconnected, action_none, "nclink: kept until the link is back"},
    {S::disconnected, E::cache_flushed, S::disconnected, action_none, "nclink"},
};

static_assert(sizeof kTable / sizeof kTable[0] == adapter_state_count * adapter_event_count, "one row per state and event");

}  // namespace

AdapterTable adapter_table() noexcept { return {kTable, sizeof kTable / sizeof kTable[0]}; }

AdapterTransition adapter_transition(AdapterState state, AdapterEvent event) noexcept {
    for (const auto& row : kTable)
        if (row.state == state && row.event == event) return {row.next, row.actions};
    return {state, action_none};
}

std::string_view to_string(AdapterState state) noexcept {
    switch (state) {
        case AdapterState::initial: return "initial";
        case AdapterState::normal: return "normal";
        case AdapterState::request: return "request";
        case AdapterState::disconnected: return "disconnected";
    }
    return "?";
}

std::string_view to_string(AdapterEvent event) noexcept {
    switch (event) {
        case AdapterEvent::initialized: return "initialized";
        case AdapterEvent::request_handled: return "request_handled";
        case AdapterEvent::response_failed: return "response_failed";
        case AdapterEvent::link_lost: return "link_lost";
        case AdapterEvent::link_restored: return "link_restored";
        case AdapterEvent::sample_due: return "sample_due";
        case AdapterEvent::model_changed: return "model_changed";
        case AdapterEvent::retry_due: return "retry_due";
        case AdapterEvent::cache_flushed: return "cache_flushed";
    }
    return "?";
}

}  // namespace nclink
