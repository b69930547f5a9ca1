// What the HTTP server's connection gate did (http/connection_gate.hpp), for
// metrics (docs/metrics.md) and tests.
#pragma once

#include <cstddef>
#include <cstdint>

namespace nclink::http {

struct ConnectionCounters {
    std::uint64_t accepted = 0;
    std::uint64_t refused_total = 0;     ///< closed at once: max_connections reached
    std::uint64_t refused_per_peer = 0;  ///< closed at once: max_connections_per_peer reached
    std::uint64_t header_timeouts = 0;   ///< closed: no whole request head within header_timeout
    std::uint64_t idle_closed = 0;       ///< closed: idle beyond keep_alive_timeout
    std::size_t open = 0;                ///< connections open now
    std::size_t waiting = 0;             ///< of them, waiting in the gate (no worker holds them)
    // Filled by HttpServer::connection_counters(), not the gate: streams run
    // on threads of their own (http/http_server.hpp).
    std::uint64_t streams_started = 0;  ///< stream answers begun
    std::uint64_t streams_refused = 0;  ///< answered 503: max_streams running already
    std::size_t streams = 0;            ///< streams running now
};

}  // namespace nclink::http
