// Puts TCP_NODELAY on the sockets paho opened to the broker.
//
// paho C 1.3.12 has no option for it and does not expose its socket. After
// every connect we scan this process's descriptors (/proc/self/fd), pick the
// TCP sockets whose peer is the broker (address and port), and set
// TCP_NODELAY on them. Another socket in the process connected to the same
// broker gets it too, which only helps. Robust across reconnects (scan again)
// and TLS (same TCP socket underneath); costs one scan per connect.
#pragma once

#include <string>
#include <vector>

namespace nclink::transport_detail {

/// Host and port of tcp://, ssl://, mqtt://, mqtts://, ws:// and wss:// URLs
/// (default ports 1883/8883/80/443). False for an unparsable URL.
bool parse_broker_url(const std::string& url, std::string& host, int& port, std::string& scheme);

/// Sets TCP_NODELAY on every TCP socket of this process connected to
/// host:port (host resolved). Returns how many sockets have it afterwards.
int apply_tcp_nodelay_to_peer(const std::string& host, int port);

/// For tests and diagnostics: the TCP sockets connected to host:port and
/// whether each has TCP_NODELAY.
struct PeerSocket {
    int fd;
    bool nodelay;
};
std::vector<PeerSocket> sockets_connected_to(const std::string& host, int port);

}  // namespace nclink::transport_detail
