#include <nclink/adapter_state.hpp>

namespace nclink {

AdapterTransition adapter_transition(AdapterState state, AdapterEvent event) noexcept {
    using S = AdapterState;
    using E = AdapterEvent;
    switch (state) {
        case S::initial:  // item 67
            if (event == E::initialized) return {S::normal, action_initialize};
            return {S::initial, action_none};  // nothing else can happen before initialization
        case S::normal:
            switch (event) {
                case E::request_answered: return {S::normal, action_send_response};        // 69
                case E::request_answer_failed: return {S::request, action_send_response};  // 69
                case E::link_lost: return {S::disconnected, action_none};                   // 70
                case E::link_restored: return {S::normal, action_none};                     // 71
                case E::sample_due: return {S::normal, action_send_sample};                 // 72
                case E::initialized: return {S::normal, action_none};
            }
            break;
        case S::request:
            switch (event) {
                case E::request_answered:
                case E::request_answer_failed: return {S::request, action_send_response};  // 74
                case E::link_lost: return {S::disconnected, action_cache_response};        // 75
                case E::link_restored: return {S::normal, action_flush_cached};            // 76
                case E::sample_due: return {S::request, action_send_sample};               // 77
                case E::initialized: return {S::request, action_none};
            }
            break;
        case S::disconnected:
            switch (event) {
                case E::request_answered:
                case E::request_answer_failed: return {S::disconnected, action_cache_response};  // 79
                case E::link_lost: return {S::disconnected, action_none};                        // 80
                case E::link_restored: return {S::normal, action_flush_cached};                  // 81
                case E::sample_due: return {S::disconnected, action_send_sample};                // 82
                case E::initialized: return {S::disconnected, action_none};
            }
            break;
    }
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
        case AdapterEvent::request_answered: return "request_answered";
        case AdapterEvent::request_answer_failed: return "request_answer_failed";
        case AdapterEvent::link_lost: return "link_lost";
        case AdapterEvent::link_restored: return "link_restored";
        case AdapterEvent::sample_due: return "sample_due";
    }
    return "?";
}

}  // namespace nclink
