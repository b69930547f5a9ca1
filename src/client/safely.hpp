// User callbacks run inside the client's threads: what one throws is logged
// and goes no further (docs/threading.md: a callback must not throw, and a
// client survives one that does).
#pragma once

#include <nclink/log.hpp>

#include <exception>

namespace nclink::client_detail {

/// Runs a user callback; what it throws is logged, never propagated into
/// the client's threads.
template <class F>
void safely(const Logger& log, F&& f) noexcept {
    try {
        f();
    } catch (const std::exception& e) {
        log.error("client: a callback threw: {}", e.what());
    } catch (...) {
        log.error("client: a callback threw");
    }
}

}  // namespace nclink::client_detail
