// A broker that refuses MQTT 5 the way RabbitMQ 3.10 does (docs/scaling.md):
// the connection of an MQTT 5 CONNECT is closed without a CONNACK, a 3.1.1
// one is accepted. It records the protocol level (MQTT 3.1.1 3.1.2.2, MQTT 5
// 3.1.2.2) of every CONNECT it reads, so a test sees what a client tried.
//
// Without an upstream it is a stand-in: it answers a 3.1.1 CONNECT with a
// CONNACK itself and keeps the connection open, reading nothing more (enough
// for a transport to be connected), or, after close_after_connack(true),
// closes it at once or a little after the CONNACK (a RabbitMQ node that
// accepts and then drops every connection, docs/scaling.md). With an upstream port it is a proxy in
// front of a real broker (a MosquittoBroker): a 3.1.1 connection is handed
// on to it byte for byte, so programs work through it.
//
// Threading: one thread of its own serves every connection; the public
// methods are thread-safe.
#pragma once

#include "support/loopback_listener.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace nclink::test {

class Mqtt5RefusingBroker {
public:
    /// `upstream_port` 0: the stand-in; else the port of the broker on
    /// 127.0.0.1 that accepted 3.1.1 connections are handed on to. `port`:
    /// where it listens (0: a free port).
    explicit Mqtt5RefusingBroker(int upstream_port = 0, int port = 0)
        : upstream_port_(upstream_port), listener_(port, 16, "MQTT 5 refusing broker") {
        thread_ = std::thread([this] { run(); });
    }
    ~Mqtt5RefusingBroker() {
        stopping_ = true;
        thread_.join();
        for (auto& c : connections_) close_both(*c);
    }
    Mqtt5RefusingBroker(const Mqtt5RefusingBroker&) = delete;
    Mqtt5RefusingBroker& operator=(const Mqtt5RefusingBroker&) = delete;

    int port() const { return listener_.port(); }
    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(listener_.port()); }
    /// The protocol level of every CONNECT read, in order (4 = 3.1.1, 5 = MQTT 5).
    std::vector<int> levels() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return levels_;
    }
    /// From now on MQTT 5 is accepted too (the control case: a broker that
    /// speaks 5); the stand-in answers it with an MQTT 5 CONNACK.
    void accept_mqtt5(bool accept) { accept_mqtt5_ = accept; }
    /// From now on the stand-in closes each connection `after` its CONNACK
    /// (0: at once): the client is connected for a moment, then loses the
    /// link. Returns how many CONNECTs were read before the change (a later
    /// one is answered the new way).
    std::size_t close_after_connack(bool close, std::chrono::milliseconds after = std::chrono::milliseconds(0)) {
        std::lock_guard<std::mutex> lock(mutex_);
        close_after_ms_ = after.count();
        close_after_connack_ = close;
        return levels_.size();
    }
    /// How many CONNECTs it has read (each a connection attempt).
    std::size_t connects() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return levels_.size();
    }
    /// For each connection accepted after close_after_connack() closed one:
    /// how long after that close it came (the client's wait before it
    /// reconnected; measured here, so a client's own delays in sending its
    /// CONNECT do not count).
    std::vector<std::chrono::milliseconds> reconnect_waits() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return reconnect_waits_;
    }
    /// Closes every accepted connection (their clients must reconnect).
    void drop_clients() {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& c : connections_) c->closed = true;
    }

private:
    struct Connection {
        int client = -1, upstream = -1;
        bool accepted = false;  // its CONNECT was 3.1.1
        bool closed = false;
        std::string head;                                               // bytes of the CONNECT read so far
        std::optional<std::chrono::steady_clock::time_point> close_at;  // close_after_connack()
    };

    // The CONNECT's protocol level once enough of it is in: fixed header
    // (type 1, 2.2.1), Remaining Length (2.2.3, 1-4 bytes), protocol name
    // (length and "MQTT"), then the level. -1: not a CONNECT; nullopt: more needed.
    static std::optional<int> level_of(const std::string& s) {
        if (s.empty()) return std::nullopt;
        if ((static_cast<unsigned char>(s[0]) >> 4) != 1) return -1;
        std::size_t pos = 1;
        while (true) {
            if (pos >= s.size()) return std::nullopt;
            if (pos > 4) return -1;
            if ((static_cast<unsigned char>(s[pos++]) & 0x80) == 0) break;
        }
        if (s.size() < pos + 2) return std::nullopt;
        const std::size_t name =
            (static_cast<std::size_t>(static_cast<unsigned char>(s[pos])) << 8) | static_cast<unsigned char>(s[pos + 1]);
        if (s.size() < pos + 2 + name + 1) return std::nullopt;
        return static_cast<unsigned char>(s[pos + 2 + name]);
    }

    void run() {
        while (!stopping_) {
            std::vector<pollfd> fds{{listener_.fd(), POLLIN, 0}};
            std::vector<Connection*> polled;  // connections are erased on this thread only
            {
                std::lock_guard<std::mutex> lock(mutex_);
                for (auto& c : connections_) {
                    if (c->closed) continue;
                    fds.push_back({c->client, POLLIN, 0});
                    fds.push_back({c->upstream, POLLIN, 0});  // -1 is ignored by poll()
                    polled.push_back(c.get());
                }
            }
            const int ready = ::poll(fds.data(), fds.size(), close_pending_ ? 2 : 50);
            std::lock_guard<std::mutex> lock(mutex_);
            if (ready > 0) {
                if (fds[0].revents & POLLIN) accept_one();
                for (std::size_t i = 0; i < polled.size(); ++i) {
                    Connection& c = *polled[i];
                    if (fds[1 + 2 * i].revents && !c.closed) from_client(c);
                    if (fds[2 + 2 * i].revents && !c.closed) pump(c, c.upstream, c.client);
                }
            }
            close_pending_ = false;
            const auto now = std::chrono::steady_clock::now();
            for (auto& c : connections_) {
                if (c->close_at && now >= *c->close_at) {
                    c->closed = true;
                    last_close_ = now;
                } else if (c->close_at) close_pending_ = true;
            }
            for (auto it = connections_.begin(); it != connections_.end();) {
                if ((*it)->closed) {
                    close_both(**it);
                    it = connections_.erase(it);
                } else {
                    ++it;
                }
            }
        }
    }

    // Under mutex_.
    void accept_one() {
        const int fd = ::accept4(listener_.fd(), nullptr, nullptr, SOCK_CLOEXEC);
        if (fd < 0) return;
        if (last_close_) {
            reconnect_waits_.push_back(std::chrono::duration_cast<std::chrono::milliseconds>(
                std::chrono::steady_clock::now() - *std::exchange(last_close_, std::nullopt)));
        }
        auto c = std::make_unique<Connection>();
        c->client = fd;
        connections_.push_back(std::move(c));
    }

    // Under mutex_.
    void from_client(Connection& c) {
        if (c.accepted && c.upstream >= 0) return pump(c, c.client, c.upstream);
        char buf[4096];
        const ssize_t n = ::recv(c.client, buf, sizeof buf, 0);
        if (n <= 0) {
            c.closed = true;
            return;
        }
        if (c.accepted) return;  // the stand-in reads the rest (PINGREQ, ...) and answers nothing
        c.head.append(buf, static_cast<std::size_t>(n));
        const auto level = level_of(c.head);
        if (!level) return;
        levels_.push_back(*level);
        if (*level != 4 && !(*level == 5 && accept_mqtt5_)) {
            c.closed = true;  // no CONNACK: how RabbitMQ 3.10 answers MQTT 5
            return;
        }
        c.accepted = true;
        if (upstream_port_ == 0) {
            // CONNACK (3.2): session present 0, accepted; MQTT 5 adds an
            // empty property list.
            const unsigned char connack4[] = {0x20, 0x02, 0x00, 0x00};
            const unsigned char connack5[] = {0x20, 0x03, 0x00, 0x00, 0x00};
            if (*level == 5) send_all(c.client, reinterpret_cast<const char*>(connack5), sizeof connack5);
            else send_all(c.client, reinterpret_cast<const char*>(connack4), sizeof connack4);
            // Closed after the CONNACK is written: the client reads it, then the end of the stream.
            if (close_after_connack_) {
                if (close_after_ms_ == 0) {
                    c.closed = true;
                    last_close_ = std::chrono::steady_clock::now();
                } else c.close_at = std::chrono::steady_clock::now() + std::chrono::milliseconds(close_after_ms_.load());
            }
            return;
        }
        c.upstream = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(static_cast<std::uint16_t>(upstream_port_));
        ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
        if (::connect(c.upstream, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
            c.closed = true;
            return;
        }
        send_all(c.upstream, c.head.data(), c.head.size());
    }

    void pump(Connection& c, int from, int to) {
        char buf[65536];
        const ssize_t n = ::recv(from, buf, sizeof buf, 0);
        if (n <= 0) {
            c.closed = true;
            return;
        }
        send_all(to, buf, static_cast<std::size_t>(n));
    }

    static void send_all(int fd, const char* data, std::size_t size) {
        while (size > 0) {
            const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
            if (n <= 0) return;
            data += n;
            size -= static_cast<std::size_t>(n);
        }
    }

    static void close_both(Connection& c) {
        if (c.client >= 0) ::close(c.client);
        if (c.upstream >= 0) ::close(c.upstream);
        c.client = c.upstream = -1;
    }

    const int upstream_port_;
    LoopbackListener listener_;
    std::atomic<bool> stopping_{false};
    std::atomic<bool> accept_mqtt5_{false};
    std::atomic<bool> close_after_connack_{false};
    std::atomic<std::int64_t> close_after_ms_{0};
    bool close_pending_ = false;  // run() only: a connection has a close_at to wait for
    std::thread thread_;
    mutable std::mutex mutex_;  // connections_, levels_, last_close_, reconnect_waits_
    std::vector<std::unique_ptr<Connection>> connections_;
    std::vector<int> levels_;
    std::optional<std::chrono::steady_clock::time_point> last_close_;  // by close_after_connack()
    std::vector<std::chrono::milliseconds> reconnect_waits_;
};

}  // namespace nclink::test
