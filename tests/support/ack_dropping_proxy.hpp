// A TCP proxy in front of a broker that can make a connection lose the
// broker's acknowledgements: on a connection marked with drop_acks_now(),
// every PUBACK (MQTT packet type 4, 3.4) from the broker is swallowed while
// everything else (CONNACK, PUBLISH, PINGRESP, ...) still passes. The client
// then sees a broker that is alive (keep-alive is answered, messages come
// in) but never drains its in-flight window: the stall of docs/performance.md "Request bursts".
// Connections made later pass everything.
//
// hold_now() makes the connections open now pass nothing either way while
// they stay open (their bytes wait in the kernel's buffers), until
// release(): a client that hangs, or whose broker node died, as the broker
// and the peers on other nodes see it (no close, no last will).
//
// refuse_shared_subscriptions() takes a SUBSCRIBE (packet type 8, 3.8) with
// a `$share/` filter away before the broker sees it, and closes its
// connection (ejabberd 23.01 at MQTT 3.1.1) or passes nothing more of it
// (RabbitMQ 3.10, which takes the filter for a topic nobody publishes):
// brokers without shared subscriptions (docs/scaling.md).
//
// Threading: one thread of its own pumps every connection; the public
// methods are thread-safe.
#pragma once

#include "support/loopback_listener.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace nclink::test {

class AckDroppingProxy {
public:
    explicit AckDroppingProxy(int broker_port) : broker_port_(broker_port), listener_(0, 16, "proxy") {
        thread_ = std::thread([this] { run(); });
    }
    ~AckDroppingProxy() {
        stopping_ = true;
        thread_.join();
        for (auto& p : pairs_) {
            ::close(p->client);
            ::close(p->broker);
        }
    }
    AckDroppingProxy(const AckDroppingProxy&) = delete;
    AckDroppingProxy& operator=(const AckDroppingProxy&) = delete;

    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(listener_.port()); }
    /// From now on the connections open now lose every PUBACK from the broker.
    void drop_acks_now() {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& p : pairs_) p->drop_acks = true;
    }
    /// From now on the connections open now pass nothing, until release().
    void hold_now() {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& p : pairs_) p->held = true;
    }
    void release() {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& p : pairs_) p->held = false;
    }
    /// From now on a SUBSCRIBE naming `$share/...` is taken away and ends its
    /// connection (`close`), or is only taken away.
    void refuse_shared_subscriptions(bool close) {
        close_on_share_ = close;
        refuse_share_ = true;
    }
    /// SUBSCRIBEs naming `$share/` taken away.
    std::uint64_t shares_refused() const { return shares_refused_; }
    std::uint64_t acks_dropped() const { return acks_dropped_; }
    std::uint64_t connections() const { return connections_; }

private:
    struct Pair {
        int client = -1, broker = -1;
        bool drop_acks = false;
        bool held = false;
        std::string from_broker;  // bytes of a packet not yet whole
        std::string from_client;  // the same, client to broker (refuse_share_ only)
        bool closed = false;
    };

    void run() {
        while (!stopping_) {
            std::vector<pollfd> fds{{listener_.fd(), POLLIN, 0}};
            std::vector<Pair*> polled;  // pairs are erased on this thread only
            {
                std::lock_guard<std::mutex> lock(mutex_);
                for (auto& p : pairs_) {
                    if (p->held) continue;
                    fds.push_back({p->client, POLLIN, 0});
                    fds.push_back({p->broker, POLLIN, 0});
                    polled.push_back(p.get());
                }
            }
            if (::poll(fds.data(), fds.size(), 50) <= 0) continue;
            if (fds[0].revents & POLLIN) accept_one();
            std::lock_guard<std::mutex> lock(mutex_);
            for (std::size_t i = 0; i < polled.size(); ++i) {
                Pair& p = *polled[i];
                if (fds[1 + 2 * i].revents && !p.closed) pump(p, p.client, p.broker, false);
                if (fds[2 + 2 * i].revents && !p.closed) pump(p, p.broker, p.client, true);
            }
            for (auto it = pairs_.begin(); it != pairs_.end();) {
                if ((*it)->closed) {
                    ::close((*it)->client);
                    ::close((*it)->broker);
                    it = pairs_.erase(it);
                } else {
                    ++it;
                }
            }
        }
    }

    void accept_one() {
        const int c = ::accept4(listener_.fd(), nullptr, nullptr, SOCK_CLOEXEC);
        if (c < 0) return;
        const int b = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(static_cast<std::uint16_t>(broker_port_));
        ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
        if (::connect(b, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
            ::close(c);
            ::close(b);
            return;
        }
        auto p = std::make_unique<Pair>();
        p->client = c;
        p->broker = b;
        std::lock_guard<std::mutex> lock(mutex_);
        pairs_.push_back(std::move(p));
        ++connections_;
    }

    void pump(Pair& p, int from, int to, bool from_broker) {
        char buf[65536];
        const ssize_t n = ::recv(from, buf, sizeof buf, 0);
        if (n <= 0) {
            p.closed = true;
            return;
        }
        if (!from_broker && !refuse_share_) return send_all(to, buf, static_cast<std::size_t>(n));
        std::string& pending = from_broker ? p.from_broker : p.from_client;
        pending.append(buf, static_cast<std::size_t>(n));
        while (const std::size_t size = whole_packet(pending)) {
            const auto type = static_cast<unsigned char>(pending[0]) >> 4;
            if (from_broker && type == 4 && p.drop_acks) {
                ++acks_dropped_;
            } else if (!from_broker && type == 8 &&
                       std::string_view(pending.data(), size).find("$share/") != std::string_view::npos) {
                ++shares_refused_;
                if (close_on_share_) {
                    p.closed = true;
                    return;
                }
            } else {
                send_all(to, pending.data(), size);
            }
            pending.erase(0, size);
        }
    }

    // The size of the whole packet at the front of `s` (fixed header byte,
    // Remaining Length (2.2.3), body); 0 while it is not all in.
    static std::size_t whole_packet(const std::string& s) {
        std::size_t length = 0, pos = 1;
        int shift = 0;
        while (pos < s.size() && pos <= 4) {
            const auto byte = static_cast<unsigned char>(s[pos++]);
            length |= static_cast<std::size_t>(byte & 0x7f) << shift;
            shift += 7;
            if ((byte & 0x80) == 0) return s.size() < pos + length ? 0 : pos + length;
        }
        return 0;
    }

    static void send_all(int fd, const char* data, std::size_t size) {
        while (size > 0) {
            const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
            if (n <= 0) return;
            data += n;
            size -= static_cast<std::size_t>(n);
        }
    }

    const int broker_port_;
    LoopbackListener listener_;
    std::atomic<bool> stopping_{false};
    std::atomic<std::uint64_t> acks_dropped_{0};
    std::atomic<std::uint64_t> shares_refused_{0};
    std::atomic<bool> refuse_share_{false};
    std::atomic<bool> close_on_share_{false};
    std::atomic<std::uint64_t> connections_{0};
    std::mutex mutex_;
    std::vector<std::unique_ptr<Pair>> pairs_;
    std::thread thread_;
};

}  // namespace nclink::test
