// One byte of a payload dropped, doubled or replaced by one of `bytes`: the
// damaged requests the decoder tests feed the fast paths and the tree alike.
#pragma once

#include <random>
#include <string>
#include <string_view>

namespace nclink::test {

inline void damage(std::string& payload, std::mt19937& random, std::string_view bytes) {
    const auto at = static_cast<std::size_t>(random() % payload.size());
    switch (random() % 3) {
        case 0: payload.erase(at, 1); break;
        case 1: payload.insert(at, 1, payload[at]); break;
        default: payload[at] = bytes[random() % bytes.size()]; break;
    }
}

}  // namespace nclink::test
