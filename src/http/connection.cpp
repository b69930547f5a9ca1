#include "http/connection.hpp"

#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <poll.h>

namespace nclink::http {

std::size_t find_head_end(std::string_view data, std::size_t from) {
    static constexpr std::string_view blank_line = "\r\n\r\n";
    const std::size_t start = from > 3 ? from - 3 : 0;  // the mark may straddle the last look
    const auto at = data.find(blank_line, start);
    return at == std::string_view::npos ? std::string::npos : at + blank_line.size();
}

bool Connection::head_ready() {
    const auto data = pending();
    const std::size_t from = scanned > consumed ? scanned - consumed : 0;
    const bool ready = find_head_end(data, from) != std::string::npos;
    // Not ready: the next look starts where this one ended. Ready: the
    // worker consumes this head, and the look after it starts afresh.
    scanned = ready ? consumed : input.size();
    return ready;
}

void Connection::compact() {
    input.erase(0, consumed);
    scanned = scanned > consumed ? scanned - consumed : 0;
    consumed = 0;
}

ConnectionStream::ConnectionStream(Connection& connection, Connection::Clock::time_point read_deadline,
                                   std::chrono::milliseconds write_timeout)
    : connection_(connection), read_deadline_(read_deadline), write_timeout_(write_timeout) {}

bool ConnectionStream::wait(short events, Connection::Clock::time_point until) const {
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Connection::Clock::now());
        if (left.count() <= 0) return false;
        pollfd p{connection_.fd, events, 0};
        const int n = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1000 * 60)));
        if (n > 0) return true;  // ready, or an error the next call reports
        if (n < 0 && errno != EINTR) return false;
    }
}

bool ConnectionStream::is_readable() const { return !connection_.pending().empty() || wait(POLLIN, read_deadline_); }

bool ConnectionStream::is_writable() const { return wait(POLLOUT, Connection::Clock::now() + write_timeout_); }

ssize_t ConnectionStream::read(char* ptr, size_t size) {
    if (size == 0) return 0;
    if (connection_.pending().empty()) {
        connection_.compact();
        char chunk[4096];
        for (;;) {
            const ssize_t n = ::recv(connection_.fd, chunk, sizeof chunk, 0);
            if (n > 0) {
                connection_.input.append(chunk, static_cast<std::size_t>(n));
                break;
            }
            if (n == 0) return 0;  // the client closed its side
            if (errno == EINTR) continue;
            if ((errno != EAGAIN && errno != EWOULDBLOCK) || !wait(POLLIN, read_deadline_)) {
                healthy_ = false;
                return -1;
            }
        }
    }
    const auto data = connection_.pending();
    const std::size_t n = std::min(size, data.size());
    std::copy_n(data.data(), n, ptr);
    connection_.consumed += n;
    return static_cast<ssize_t>(n);
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
    if (!healthy_) return -1;
    const auto now = Connection::Clock::now();
    if (streaming_) {
        write_deadline_ = now + write_timeout_;
    } else if (write_deadline_ == Connection::Clock::time_point{}) {
        write_deadline_ = now + write_timeout_;
    }
    for (;;) {
        const ssize_t n = ::send(connection_.fd, ptr, size, MSG_NOSIGNAL);
        if (n >= 0) return n;
        if (errno == EINTR) continue;
        if ((errno != EAGAIN && errno != EWOULDBLOCK) || !wait(POLLOUT, write_deadline_)) {
            healthy_ = false;
            return -1;
        }
    }
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
    ip = connection_.peer_ip;
    port = connection_.peer_port;
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
    ip = connection_.local_ip;
    port = connection_.local_port;
}

}  // namespace nclink::http
