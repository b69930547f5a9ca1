// The application state machine of the NC-Link state-machine patent text
// (the application state machine, docs/state-machines.md): initial, normal, request, disconnected. The
// Client (client.hpp) drives it; docs/client.md, "State machine", shows the
// table and where nclink refines it.
#pragma once

#include <nclink/export.hpp>
#include <string_view>

namespace nclink {

enum class ClientState {
    initial,       ///< started, the link has not come up yet (not started: also initial)
    normal,        ///< connected, no request outstanding
    request,       ///< connected, at least one request waiting for its response
    disconnected,  ///< the link was up and is down now; new requests are queued
};

enum class ClientEvent {
    request_made,       ///< the application asks for something (item 11/17/23)
    response_received,  ///< a response (or the request's timeout) completed a request; others still outstanding
    last_response,      ///< ... and none is outstanding any more (item 18)
    stray_response,     ///< a response no outstanding request waits for (item 12: dropped)
    link_lost,          ///< item 13/19/25
    link_restored,      ///< item 14/20/26 (the first connection is the initialization event of item 9)
    sample_received,    ///< item 15/21/27
};

/// What the client does on a transition (a bit set).
enum ClientAction : unsigned {
    client_action_none = 0,
    client_action_register = 1u << 0,         ///< item 9: register with the agent (Client::connect() does)
    client_action_send_request = 1u << 1,     ///< publish the request DTU
    client_action_queue_request = 1u << 2,    ///< keep the request until the link is back (item 23)
    client_action_send_queued = 1u << 3,      ///< publish the queued requests, in order (item 26)
    client_action_handle_response = 1u << 4,  ///< hand the response to the request's caller
    client_action_drop_response = 1u << 5,    ///< item 12
    client_action_handle_sample = 1u << 6,    ///< hand the sample to the subscriptions
};

struct NCLINK_API ClientTransition {
    ClientState next;
    unsigned actions;
};

/// The transition table, item by item of the application state machine (docs/state-machines.md). `queued` says whether
/// requests are queued (decides item 26: request or normal after
/// reconnecting); `outstanding` whether requests sent before the link
/// dropped still wait for their answer (nclink keeps them: the transport
/// re-sends unacknowledged QoS 1 messages, so their answers may still come).
/// Pure and thread-safe.
NCLINK_API ClientTransition client_transition(ClientState state, ClientEvent event, bool queued = false,
                                              bool outstanding = false) noexcept;

NCLINK_API std::string_view to_string(ClientState state) noexcept;
NCLINK_API std::string_view to_string(ClientEvent event) noexcept;

}  // namespace nclink
