// The HTTP limits of a program's /metrics endpoint (nclink-agent --metrics,
// nclink-sim --metrics): the "metrics" section of the agent's and the
// adapter's configuration, with the keys and meanings of the bridge's http_*
// settings (docs/bridge.md "Slow and idle clients", docs/metrics.md). The
// SDK's Adapter and Agent serve no HTTP; the programs read these.
#pragma once

#include <nclink/export.hpp>

#include <chrono>
#include <cstddef>

namespace nclink {

struct NCLINK_API HttpLimits {
    std::size_t workers = 2;                         ///< "http_workers": request workers (at least 1)
    std::chrono::milliseconds header_timeout{3000};  ///< "http_header_timeout_ms": a request head must be whole within it (408)
    std::chrono::milliseconds keep_alive{5000};      ///< "http_keep_alive_ms": an idle keep-alive connection is closed after it
    std::chrono::milliseconds write_timeout{5000};   ///< "http_write_timeout_ms": a client must take an answer within it
    std::size_t max_connections = 512;               ///< "http_max_connections": connections open at once (at least 1)
    std::size_t max_connections_per_peer = 64;       ///< "http_max_connections_per_peer": from one address; 0 = no cap

    bool operator==(const HttpLimits& o) const {
        return workers == o.workers && header_timeout == o.header_timeout && keep_alive == o.keep_alive &&
               write_timeout == o.write_timeout && max_connections == o.max_connections &&
               max_connections_per_peer == o.max_connections_per_peer;
    }
    bool operator!=(const HttpLimits& o) const { return !(*this == o); }
};

}  // namespace nclink
