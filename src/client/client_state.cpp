#include <nclink/client_state.hpp>

namespace nclink {

ClientTransition client_transition(ClientState state, ClientEvent event, bool queued, bool outstanding) noexcept {
    using S = ClientState;
    using E = ClientEvent;
    switch (state) {
        case S::initial:  // item 9; before the first connection requests wait like while disconnected
            switch (event) {
                case E::link_restored:
                    if (queued) return {S::request, client_action_register | client_action_send_queued};
                    return {S::normal, client_action_register};
                case E::request_made: return {S::initial, client_action_queue_request};
                case E::response_received:
                case E::last_response: return {S::initial, client_action_handle_response};
                case E::stray_response: return {S::initial, client_action_drop_response};
                case E::link_lost: return {S::initial, client_action_none};
                case E::sample_received: return {S::initial, client_action_handle_sample};
            }
            break;
        case S::normal:
            switch (event) {
                case E::request_made: return {S::request, client_action_send_request};    // 11
                case E::stray_response: return {S::normal, client_action_drop_response};  // 12
                case E::response_received:
                case E::last_response: return {S::normal, client_action_handle_response};
                case E::link_lost: return {S::disconnected, client_action_none};           // 13
                case E::link_restored: return {S::normal, client_action_none};             // 14
                case E::sample_received: return {S::normal, client_action_handle_sample};  // 15
            }
            break;
        case S::request:
            switch (event) {
                case E::request_made: return {S::request, client_action_send_request};          // 17
                case E::response_received: return {S::request, client_action_handle_response};  // others still wait
                case E::last_response: return {S::normal, client_action_handle_response};       // 18
                case E::stray_response: return {S::request, client_action_drop_response};
                case E::link_lost: return {S::disconnected, client_action_none};            // 19
                case E::link_restored: return {S::request, client_action_none};             // 20
                case E::sample_received: return {S::request, client_action_handle_sample};  // 21
            }
            break;
        case S::disconnected:
            switch (event) {
                case E::request_made: return {S::disconnected, client_action_queue_request};  // 23
                case E::response_received:
                case E::last_response: return {S::disconnected, client_action_handle_response};  // 24
                case E::stray_response: return {S::disconnected, client_action_drop_response};
                case E::link_lost: return {S::disconnected, client_action_none};  // 25
                case E::link_restored:                                            // 26
                    if (queued) return {S::request, client_action_send_queued};
                    return {outstanding ? S::request : S::normal, client_action_none};
                case E::sample_received: return {S::disconnected, client_action_handle_sample};  // 27
            }
            break;
    }
    return {state, client_action_none};
}

std::string_view to_string(ClientState state) noexcept {
    switch (state) {
        case ClientState::initial: return "initial";
        case ClientState::normal: return "normal";
        case ClientState::request: return "request";
        case ClientState::disconnected: return "disconnected";
    }
    return "?";
}

std::string_view to_string(ClientEvent event) noexcept {
    switch (event) {
        case ClientEvent::request_made: return "request_made";
        case ClientEvent::response_received: return "response_received";
        case ClientEvent::last_response: return "last_response";
        case ClientEvent::stray_response: return "stray_response";
        case ClientEvent::link_lost: return "link_lost";
        case ClientEvent::link_restored: return "link_restored";
        case ClientEvent::sample_received: return "sample_received";
    }
    return "?";
}

}  // namespace nclink
