#include "http/connection_gate.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace nclink::http {

namespace {

void address_of(const sockaddr_storage& a, std::string& ip, int& port) {
    char text[INET6_ADDRSTRLEN] = {};
    if (a.ss_family == AF_INET) {
        const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
        ::inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
        port = ntohs(v4.sin_port);
    } else if (a.ss_family == AF_INET6) {
        const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
        ::inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
        port = ntohs(v6.sin6_port);
    }
    ip = text;
}

// The answer to a request head that did not arrive in time. A fixed text,
// written without looking at what the peer sent.
constexpr std::string_view request_timeout_answer =
    "HTTP/1.1 408 Request Timeout\r\nConnection: close\r\nContent-Length: 0\r\n\r\n";

}  // namespace

ConnectionGate::ConnectionGate(GateOptions options, Logger logger) : options_(options), logger_(std::move(logger)) {}

ConnectionGate::~ConnectionGate() {
    stop();
    if (listen_fd_ >= 0) ::close(listen_fd_);
    if (wake_fd_ >= 0) ::close(wake_fd_);
}

Result<int> ConnectionGate::bind(const std::string& host, int port) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE;
    addrinfo* found = nullptr;
    const std::string service = std::to_string(port);
    if (::getaddrinfo(host.empty() ? nullptr : host.c_str(), service.c_str(), &hints, &found) != 0 || !found)
        return make_error(ErrorCode::unavailable, "http: cannot resolve " + host);
    std::string why = "no address";
    for (addrinfo* a = found; a; a = a->ai_next) {
        const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol);
        if (fd < 0) continue;
        // SO_REUSEADDR lets a restart rebind at once; without SO_REUSEPORT a
        // port another server holds is an error, not silently shared.
        int yes = 1;
        ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0 && ::listen(fd, SOMAXCONN) == 0) {
            listen_fd_ = fd;
            break;
        }
        why = std::strerror(errno);
        ::close(fd);
    }
    ::freeaddrinfo(found);
    if (listen_fd_ < 0) return make_error(ErrorCode::unavailable, "http: cannot bind " + host + ":" + service + " (" + why + ")");
    sockaddr_storage bound{};
    socklen_t length = sizeof bound;
    ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &length);
    std::string ip;
    int bound_port = 0;
    address_of(bound, ip, bound_port);
    wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (wake_fd_ < 0) return make_error(ErrorCode::unavailable, "http: eventfd failed");
    return bound_port;
}

void ConnectionGate::start(Serve serve) {
    serve_ = std::move(serve);
    thread_ = std::thread([this] { run(); });
}

void ConnectionGate::wake() {
    const std::uint64_t one = 1;
    if (wake_fd_ >= 0) {
        [[maybe_unused]] auto ignored = ::write(wake_fd_, &one, sizeof one);
    }
}

void ConnectionGate::release(int fd, const std::string& peer) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        with_workers_.erase(fd);
        auto it = per_peer_.find(peer);
        if (it != per_peer_.end() && --it->second == 0) per_peer_.erase(it);
        --open_;
    }
    ::close(fd);
}

void ConnectionGate::close(std::unique_ptr<Connection> connection) {
    if (connection) release(connection->fd, connection->peer_ip);
}

void ConnectionGate::give_back(std::unique_ptr<Connection> connection) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!stopping_) {
            with_workers_.erase(connection->fd);
            returned_.push_back(std::move(connection));
        }
    }
    if (connection) {
        close(std::move(connection));
        return;
    }
    wake();
}

void ConnectionGate::accept_all() {
    for (;;) {
        sockaddr_storage peer{};
        socklen_t length = sizeof peer;
        const int fd = ::accept4(listen_fd_, reinterpret_cast<sockaddr*>(&peer), &length, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) {
            if (errno == EINTR) continue;
            if (errno == EMFILE || errno == ENFILE) {
                // Out of descriptors: the pending connection stays in the
                // backlog; wait a little rather than spin on a readable socket.
                logger_.warn("http: cannot accept a connection: {}", std::strerror(errno));
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
            return;
        }
        auto c = std::make_unique<Connection>();
        c->fd = fd;
        address_of(peer, c->peer_ip, c->peer_port);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            const bool full = open_ >= options_.max_connections;
            const bool peer_full = options_.max_connections_per_peer > 0 && per_peer_.count(c->peer_ip) &&
                                   per_peer_[c->peer_ip] >= options_.max_connections_per_peer;
            if (full || peer_full) {
                ++(full ? counters_.refused_total : counters_.refused_per_peer);
                ::close(fd);
                continue;
            }
            ++open_;
            ++per_peer_[c->peer_ip];
            ++counters_.accepted;
        }
        int yes = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
        sockaddr_storage local{};
        length = sizeof local;
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length);
        address_of(local, c->local_ip, c->local_port);
        c->idle = false;  // a new connection owes its first head within header_timeout
        c->deadline = Connection::Clock::now() + options_.header_timeout;
        waiting_.push_back(std::move(c));
    }
}

void ConnectionGate::on_readable(std::unique_ptr<Connection>& c, Connection::Clock::time_point now) {
    bool peer_closed = false;
    char chunk[4096];
    while (c->pending().size() < options_.max_head_bytes) {
        const ssize_t n = ::recv(c->fd, chunk, sizeof chunk, 0);
        if (n > 0) {
            if (c->idle) {  // the first byte of the next request starts its head's clock
                c->idle = false;
                c->deadline = now + options_.header_timeout;
            }
            c->input.append(chunk, static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
        peer_closed = true;  // end of stream or an error
        break;
    }
    if (c->head_ready() || c->pending().size() >= options_.max_head_bytes) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            with_workers_.insert(c->fd);
        }
        serve_(std::move(c));
        return;
    }
    if (peer_closed) {
        release(c->fd, c->peer_ip);
        c.reset();
    }
}

void ConnectionGate::expire(std::unique_ptr<Connection>& c) {
    if (!c->idle && !c->pending().empty()) {
        [[maybe_unused]] auto ignored =
            ::send(c->fd, request_timeout_answer.data(), request_timeout_answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ++(c->idle ? counters_.idle_closed : counters_.header_timeouts);
    }
    release(c->fd, c->peer_ip);
    c.reset();
}

void ConnectionGate::run() {
    std::vector<pollfd> fds;
    while (!stopping_) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            for (auto& r : returned_) waiting_.push_back(std::move(r));
            returned_.clear();
            counters_.waiting = waiting_.size();
        }
        auto now = Connection::Clock::now();
        auto next = now + std::chrono::seconds(1);
        fds.clear();
        fds.push_back({listen_fd_, POLLIN, 0});
        fds.push_back({wake_fd_, POLLIN, 0});
        for (const auto& c : waiting_) {
            fds.push_back({c->fd, POLLIN, 0});
            next = std::min(next, c->deadline);
        }
        const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count() + 1;
        const int n = ::poll(fds.data(), fds.size(), static_cast<int>(std::max<long long>(wait, 0)));
        if (n < 0 && errno != EINTR) {
            logger_.error("http: poll failed: {}", std::strerror(errno));
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
            continue;
        }
        now = Connection::Clock::now();
        if (fds[1].revents) {
            std::uint64_t count = 0;
            [[maybe_unused]] auto ignored = ::read(wake_fd_, &count, sizeof count);
        }
        // fds[2 + i] is waiting_[i] for the connections polled in this round.
        const std::size_t polled = fds.size() - 2;
        for (std::size_t i = 0; i < polled; ++i)
            if (fds[2 + i].revents & (POLLIN | POLLHUP | POLLERR)) on_readable(waiting_[i], now);
        for (auto& c : waiting_)
            if (c && now >= c->deadline) expire(c);
        waiting_.erase(std::remove(waiting_.begin(), waiting_.end(), nullptr), waiting_.end());
        if (fds[0].revents & POLLIN) accept_all();
    }
    for (auto& c : waiting_) release(c->fd, c->peer_ip);
    waiting_.clear();
}

void ConnectionGate::stop() {
    if (stopping_.exchange(true)) return;
    wake();
    if (thread_.joinable()) thread_.join();
    std::vector<std::unique_ptr<Connection>> returned;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        returned.swap(returned_);
    }
    for (auto& c : returned) release(c->fd, c->peer_ip);
    if (listen_fd_ >= 0) {
        ::close(listen_fd_);
        listen_fd_ = -1;
    }
}

void ConnectionGate::interrupt_served() {
    // The descriptors stay open (their workers close them); shutting them
    // down makes every read and write on them end at once.
    std::lock_guard<std::mutex> lock(mutex_);
    for (int fd : with_workers_) ::shutdown(fd, SHUT_RDWR);
}

ConnectionCounters ConnectionGate::counters() const {
    std::lock_guard<std::mutex> lock(mutex_);
    ConnectionCounters out = counters_;
    out.open = open_;
    return out;
}

}  // namespace nclink::http
