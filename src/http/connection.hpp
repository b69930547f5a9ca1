// One accepted HTTP connection and the byte stream cpp-httplib reads and
// writes it through (docs/bridge.md "Slow and idle clients").
//
// The connection gate (http/connection_gate.hpp) reads the bytes of a request
// head into `Connection::input` while the connection waits in its poll set,
// and hands the connection to a worker only once the head is complete; the
// worker then lets cpp-httplib parse it from the same buffer through
// ConnectionStream. nclink parses no HTTP: the only thing looked for here is
// the blank line (CR LF CR LF) that ends every request head (RFC 9112 2.1),
// the same framing mark that tells any HTTP reader "the head is complete";
// what the head says is left to the library.
//
// Threading: a Connection belongs to one thread at a time — the gate's while
// it waits, one worker while a request is served; the hand-over goes through
// the gate's mutex.
#pragma once

#include <httplib.h>

#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>

namespace nclink::http {

/// The offset just past the first CR LF CR LF in `data` at or after `from`
/// (scanning may start a few bytes early), or std::string::npos.
std::size_t find_head_end(std::string_view data, std::size_t from = 0);

struct Connection {
    using Clock = std::chrono::steady_clock;

    int fd = -1;
    std::string peer_ip;
    int peer_port = 0;
    std::string local_ip;
    int local_port = 0;
    /// Bytes received and not yet consumed by the library, from `consumed` on.
    std::string input;
    std::size_t consumed = 0;
    std::size_t scanned = 0;  ///< find_head_end() has looked at input up to here
    /// The gate closes the connection when this passes while it waits.
    Clock::time_point deadline{};
    std::size_t requests = 0;  ///< requests served on it so far
    bool idle = true;          ///< waiting between requests (no byte of the next one yet)

    std::string_view pending() const { return std::string_view(input).substr(consumed); }
    /// True when a whole request head waits in `input`.
    bool head_ready();
    /// Drops consumed bytes so the buffer does not grow with a long connection.
    void compact();
};

/// The connection as cpp-httplib's Stream, for one request: reads come from
/// `input` first, then from the socket until `read_deadline`; each write
/// waits for the socket at most `write_timeout`, and, unless streaming() was
/// called, all writes of the response end by the first write + write_timeout,
/// so a client that reads slowly cannot hold a worker for long.
class ConnectionStream final : public httplib::Stream {
public:
    ConnectionStream(Connection& connection, Connection::Clock::time_point read_deadline, std::chrono::milliseconds write_timeout);

    bool is_readable() const override;
    bool is_writable() const override;
    ssize_t read(char* ptr, size_t size) override;
    ssize_t write(const char* ptr, size_t size) override;
    void get_remote_ip_and_port(std::string& ip, int& port) const override;
    void get_local_ip_and_port(std::string& ip, int& port) const override;
    socket_t socket() const override { return connection_.fd; }

    /// The response is a stream (SSE): each write has its own timeout.
    void streaming() { streaming_ = true; }
    /// False once a read or write failed or timed out.
    bool healthy() const { return healthy_; }

private:
    bool wait(short events, Connection::Clock::time_point until) const;

    Connection& connection_;
    Connection::Clock::time_point read_deadline_;
    std::chrono::milliseconds write_timeout_;
    Connection::Clock::time_point write_deadline_{};
    bool streaming_ = false;
    bool healthy_ = true;
};

}  // namespace nclink::http
