#include <nclink/transport.hpp>

namespace nclink {

std::string_view to_string(LinkState state) noexcept {
    switch (state) {
        case LinkState::disconnected: return "disconnected";
        case LinkState::connecting: return "connecting";
        case LinkState::connected: return "connected";
    }
    return "?";
}

}  // namespace nclink
