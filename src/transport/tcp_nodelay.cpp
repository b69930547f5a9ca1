#include "transport/tcp_nodelay.hpp"

#include <arpa/inet.h>
#include <dirent.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace nclink::transport_detail {
namespace {

struct Endpoint {
    sockaddr_storage addr{};
    socklen_t len = 0;
};

std::vector<Endpoint> resolve(const std::string& host, int port) {
    std::vector<Endpoint> out;
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* list = nullptr;
    const std::string service = std::to_string(port);
    if (getaddrinfo(host.c_str(), service.c_str(), &hints, &list) != 0) return out;
    for (addrinfo* ai = list; ai; ai = ai->ai_next) {
        Endpoint e;
        std::memcpy(&e.addr, ai->ai_addr, ai->ai_addrlen);
        e.len = static_cast<socklen_t>(ai->ai_addrlen);
        out.push_back(e);
    }
    freeaddrinfo(list);
    return out;
}

bool same_endpoint(const sockaddr_storage& a, const sockaddr_storage& b) {
    if (a.ss_family != b.ss_family) {
        // An IPv4 peer may show up as IPv4-mapped IPv6 on a dual-stack socket.
        const sockaddr_storage& v6 = a.ss_family == AF_INET6 ? a : b;
        const sockaddr_storage& v4 = a.ss_family == AF_INET ? a : b;
        if (v6.ss_family != AF_INET6 || v4.ss_family != AF_INET) return false;
        const auto& s6 = reinterpret_cast<const sockaddr_in6&>(v6);
        const auto& s4 = reinterpret_cast<const sockaddr_in&>(v4);
        return IN6_IS_ADDR_V4MAPPED(&s6.sin6_addr) && s6.sin6_port == s4.sin_port &&
               std::memcmp(&s6.sin6_addr.s6_addr[12], &s4.sin_addr, 4) == 0;
    }
    if (a.ss_family == AF_INET) {
        const auto& x = reinterpret_cast<const sockaddr_in&>(a);
        const auto& y = reinterpret_cast<const sockaddr_in&>(b);
        return x.sin_port == y.sin_port && x.sin_addr.s_addr == y.sin_addr.s_addr;
    }
    if (a.ss_family == AF_INET6) {
        const auto& x = reinterpret_cast<const sockaddr_in6&>(a);
        const auto& y = reinterpret_cast<const sockaddr_in6&>(b);
        return x.sin6_port == y.sin6_port && std::memcmp(&x.sin6_addr, &y.sin6_addr, sizeof x.sin6_addr) == 0;
    }
    return false;
}

}  // namespace

bool parse_broker_url(const std::string& url, std::string& host, int& port, std::string& scheme) {
    const auto sep = url.find("://");
    if (sep == std::string::npos) return false;
    scheme = url.substr(0, sep);
    std::string rest = url.substr(sep + 3);
    if (const auto slash = rest.find('/'); slash != std::string::npos) rest.resize(slash);  // ws path
    if (rest.empty()) return false;
    int default_port = 0;
    if (scheme == "tcp" || scheme == "mqtt") default_port = 1883;
    else if (scheme == "ssl" || scheme == "mqtts") default_port = 8883;
    else if (scheme == "ws") default_port = 80;
    else if (scheme == "wss") default_port = 443;
    else return false;
    std::string port_text;
    if (rest.front() == '[') {  // [v6]:port
        const auto close = rest.find(']');
        if (close == std::string::npos) return false;
        host = rest.substr(1, close - 1);
        if (close + 1 < rest.size()) {
            if (rest[close + 1] != ':') return false;
            port_text = rest.substr(close + 2);
        }
    } else {
        const auto colon = rest.rfind(':');
        host = rest.substr(0, colon);
        if (colon != std::string::npos) port_text = rest.substr(colon + 1);
    }
    if (host.empty()) return false;
    port = default_port;
    if (!port_text.empty()) {
        char* end = nullptr;
        const long value = std::strtol(port_text.c_str(), &end, 10);
        if (*end != '\0' || value <= 0 || value > 65535) return false;
        port = static_cast<int>(value);
    }
    return true;
}

std::vector<PeerSocket> sockets_connected_to(const std::string& host, int port) {
    std::vector<PeerSocket> found;
    const auto targets = resolve(host, port);
    if (targets.empty()) return found;
    DIR* dir = opendir("/proc/self/fd");
    if (!dir) return found;
    while (dirent* entry = readdir(dir)) {
        char* end = nullptr;
        const long fd = std::strtol(entry->d_name, &end, 10);
        if (*end != '\0' || fd < 0 || fd == dirfd(dir)) continue;
        struct stat st {};
        if (fstat(static_cast<int>(fd), &st) != 0 || !S_ISSOCK(st.st_mode)) continue;
        int type = 0;
        socklen_t type_len = sizeof type;
        if (getsockopt(static_cast<int>(fd), SOL_SOCKET, SO_TYPE, &type, &type_len) != 0 || type != SOCK_STREAM) continue;
        sockaddr_storage peer{};
        socklen_t peer_len = sizeof peer;
        if (getpeername(static_cast<int>(fd), reinterpret_cast<sockaddr*>(&peer), &peer_len) != 0) continue;
        if (peer.ss_family != AF_INET && peer.ss_family != AF_INET6) continue;
        bool match = false;
        for (const auto& t : targets) match = match || same_endpoint(peer, t.addr);
        if (!match) continue;
        int nodelay = 0;
        socklen_t len = sizeof nodelay;
        getsockopt(static_cast<int>(fd), IPPROTO_TCP, TCP_NODELAY, &nodelay, &len);
        found.push_back(PeerSocket{static_cast<int>(fd), nodelay != 0});
    }
    closedir(dir);
    return found;
}

int apply_tcp_nodelay_to_peer(const std::string& host, int port) {
    int count = 0;
    for (const auto& s : sockets_connected_to(host, port)) {
        int on = 1;
        if (s.nodelay || setsockopt(s.fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on) == 0) ++count;
    }
    return count;
}

}  // namespace nclink::transport_detail
