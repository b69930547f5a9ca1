// What the client counts, read by Client::stats() (client.cpp). Each counter
// is bumped by the one thread that owns its event (dispatch thread, or the
// caller of a request) and read from any thread: atomics, relaxed use.
#pragma once

#include <atomic>
#include <cstdint>

namespace nclink::client_detail {

struct ClientCounters {
    std::atomic<std::uint64_t> requests{0}, responses{0}, timeouts{0}, late{0}, unmatched{0}, malformed{0}, unreachable{0},
        samples{0}, notifications{0}, queued{0}, events{0}, duplicates{0}, keepalives{0}, resent{0};
};

}  // namespace nclink::client_detail
