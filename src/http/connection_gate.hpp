// The accept side of the HTTP server (docs/bridge.md "Slow and idle
// clients"): one thread owns the listening socket and every connection that
// is not being served — new ones that have not yet sent a whole request head,
// and idle keep-alive ones between requests — in one poll() set. A worker
// gets a connection only when a whole request head is buffered, so a peer
// that connects and sends nothing, half a request line, or a byte a second
// costs a file descriptor and never a worker:
//
//  - a connection whose head is not complete `header_timeout` after it was
//    accepted (or after the first byte of a later request on it) is closed,
//    with a "408 Request Timeout" if it had sent anything (RFC 9110 15.5.9);
//  - an idle keep-alive connection is closed after `keep_alive_timeout`;
//  - at most `max_connections` are open at once and at most
//    `max_connections_per_peer` from one address; beyond that a new
//    connection is closed at once;
//  - a head larger than `max_head_bytes` is handed on as it is, so the
//    library answers it (400/414).
//
// The gate looks only for the blank line that ends a head
// (http/connection.hpp); it parses nothing.
//
// Threading: the gate's thread runs from start() to stop(); `serve` runs on
// it (it should only queue the connection); give_back() and close() are
// called from workers; counters() from any thread.
#pragma once

#include "http/connection.hpp"
#include "http/connection_counters.hpp"

#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace nclink::http {

struct GateOptions {
    std::chrono::milliseconds header_timeout{3000};
    std::chrono::milliseconds keep_alive_timeout{5000};
    std::size_t max_connections = 512;
    std::size_t max_connections_per_peer = 64;  ///< 0: no cap per peer
    std::size_t max_head_bytes = 64 * 1024;
};

class ConnectionGate {
public:
    using Serve = std::function<void(std::unique_ptr<Connection>)>;

    ConnectionGate(GateOptions options, Logger logger);
    ~ConnectionGate();  ///< stop()s
    ConnectionGate(const ConnectionGate&) = delete;
    ConnectionGate& operator=(const ConnectionGate&) = delete;

    /// Binds host:port (0: any free port) with SO_REUSEADDR.
    Result<int> bind(const std::string& host, int port);
    /// Runs the gate's thread; `serve` gets each connection with a whole head.
    void start(Serve serve);
    /// A served connection goes back to wait for its next request.
    void give_back(std::unique_ptr<Connection> connection);
    /// Closes a connection the gate handed out.
    void close(std::unique_ptr<Connection> connection);
    /// Stops the thread, closes every waiting connection and the listening
    /// socket. Connections with workers stay as they are. Idempotent.
    void stop();
    /// Shuts down (without closing) the connections with workers, so their
    /// reads and writes end at once. After stop().
    void interrupt_served();

    ConnectionCounters counters() const;

private:
    void run();
    void accept_all();
    void on_readable(std::unique_ptr<Connection>& connection, Connection::Clock::time_point now);
    void expire(std::unique_ptr<Connection>& connection);
    void release(int fd, const std::string& peer);
    void wake();

    GateOptions options_;
    Logger logger_;
    Serve serve_;
    int listen_fd_ = -1;
    int wake_fd_ = -1;
    std::thread thread_;
    std::atomic<bool> stopping_{false};

    std::vector<std::unique_ptr<Connection>> waiting_;  // gate thread only

    mutable std::mutex mutex_;
    std::vector<std::unique_ptr<Connection>> returned_;  // given back, not yet in the poll set
    std::set<int> with_workers_;                         // fds served now
    std::map<std::string, std::size_t> per_peer_;
    std::size_t open_ = 0;
    ConnectionCounters counters_;
};

}  // namespace nclink::http
