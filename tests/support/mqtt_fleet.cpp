#include "support/mqtt_fleet.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <stdexcept>

namespace nclink::test {

namespace {

void put_u16(std::string& out, std::size_t v) {
    out.push_back(static_cast<char>((v >> 8) & 0xff));
    out.push_back(static_cast<char>(v & 0xff));
}

void put_str(std::string& out, const std::string& s) {
    put_u16(out, s.size());
    out += s;
}

std::string packet(std::uint8_t type, const std::string& body) {
    std::string out(1, static_cast<char>(type));
    std::size_t len = body.size();
    do {
        std::uint8_t byte = len % 128;
        len /= 128;
        if (len > 0) byte |= 0x80;
        out.push_back(static_cast<char>(byte));
    } while (len > 0);
    return out + body;
}

}  // namespace

struct MqttFleet::Peer {
    FleetClient config;
    int fd = -1;
    bool tcp_up = false;
    bool accepted = false;
    bool closed = false;
    std::string in, out;
    std::uint16_t next_id = 1;
    std::vector<Message> received;
    std::chrono::steady_clock::time_point last_sent = std::chrono::steady_clock::now();

    std::uint16_t id() {
        if (next_id == 0) next_id = 1;
        return next_id++;
    }

    void send_publish(const Message& m) {
        std::string body;
        put_str(body, m.topic);
        if (m.qos > 0) put_u16(body, id());
        body += m.payload;
        const std::uint8_t type = static_cast<std::uint8_t>(0x30 | (m.qos > 0 ? 0x02 : 0) | (m.retained ? 1 : 0));
        out += packet(type, body);
    }

    void send_connect() {
        std::string body;
        put_str(body, "MQTT");
        body.push_back(4);
        std::uint8_t flags = 0x02;  // clean session
        if (config.will)
            flags |= static_cast<std::uint8_t>(0x04 | (config.will->qos > 0 ? 0x08 : 0) | (config.will->retained ? 0x20 : 0));
        body.push_back(static_cast<char>(flags));
        put_u16(body, static_cast<std::size_t>(config.keep_alive_s));
        put_str(body, config.client_id);
        if (config.will) {
            put_str(body, config.will->topic);
            put_str(body, config.will->payload);
        }
        out += packet(0x10, body);
    }

    void on_connack() {
        accepted = true;
        if (!config.subscriptions.empty()) {
            std::string body;
            put_u16(body, id());
            for (const auto& f : config.subscriptions) {
                put_str(body, f);
                body.push_back(1);
            }
            out += packet(0x82, body);
        }
        for (const auto& m : config.on_connect) send_publish(m);
    }

    // Parses complete packets from `in`; returns the number of PUBLISHes received.
    std::size_t parse() {
        std::size_t publishes = 0;
        for (;;) {
            if (in.size() < 2) return publishes;
            std::size_t len = 0, mult = 1, pos = 1;
            bool complete = false;
            while (pos < in.size() && pos < 5) {
                const auto byte = static_cast<std::uint8_t>(in[pos++]);
                len += (byte & 0x7f) * mult;
                mult *= 128;
                if (!(byte & 0x80)) {
                    complete = true;
                    break;
                }
            }
            if (!complete || in.size() < pos + len) return publishes;
            const auto type = static_cast<std::uint8_t>(in[0]);
            const std::string body = in.substr(pos, len);
            in.erase(0, pos + len);
            switch (type >> 4) {
                case 2:  // CONNACK
                    if (body.size() >= 2 && body[1] == 0) on_connack();
                    break;
                case 3: {  // PUBLISH
                    if (body.size() < 2) break;
                    const std::size_t tlen = (static_cast<std::uint8_t>(body[0]) << 8) | static_cast<std::uint8_t>(body[1]);
                    std::size_t at = 2 + tlen;
                    const int qos = (type >> 1) & 3;
                    Message m;
                    m.topic = body.substr(2, tlen);
                    m.qos = qos;
                    m.retained = (type & 1) != 0;
                    if (qos > 0 && at + 2 <= body.size()) {
                        std::string ack;
                        ack.push_back(body[at]);
                        ack.push_back(body[at + 1]);
                        out += packet(0x40, ack);
                        at += 2;
                    }
                    m.payload = at <= body.size() ? body.substr(at) : std::string();
                    received.push_back(std::move(m));
                    ++publishes;
                    break;
                }
                default: break;  // PUBACK, SUBACK, PINGRESP
            }
        }
    }
};

MqttFleet::MqttFleet(int port) : port_(port) {
    if (::pipe(wake_pipe_) != 0) throw std::runtime_error("pipe failed");
    ::fcntl(wake_pipe_[0], F_SETFL, O_NONBLOCK);
    ::fcntl(wake_pipe_[1], F_SETFL, O_NONBLOCK);
    thread_ = std::thread([this] { run(); });
}

MqttFleet::~MqttFleet() {
    stopping_ = true;
    wake();
    if (thread_.joinable()) thread_.join();
    for (auto& [id, peer] : peers_)
        if (peer->fd >= 0) ::close(peer->fd);
    ::close(wake_pipe_[0]);
    ::close(wake_pipe_[1]);
}

void MqttFleet::wake() {
    const char c = 1;
    (void)!::write(wake_pipe_[1], &c, 1);
}

void MqttFleet::add(FleetClient client) {
    auto peer = std::make_unique<Peer>();
    peer->config = std::move(client);
    peer->fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
    if (peer->fd < 0) throw std::runtime_error("socket failed (file descriptor limit?)");
    const int one = 1;
    ::setsockopt(peer->fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port_));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const int rc = ::connect(peer->fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
    if (rc != 0 && errno != EINPROGRESS) {
        ::close(peer->fd);
        throw std::runtime_error("connect failed");
    }
    peer->send_connect();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const std::string id = peer->config.client_id;
        if (auto it = peers_.find(id); it != peers_.end() && it->second->fd >= 0) ::close(it->second->fd);
        peers_[id] = std::move(peer);
    }
    wake();
}

void MqttFleet::drop(const std::string& client_id) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = peers_.find(client_id);
    if (it == peers_.end() || it->second->fd < 0) return;
    ::shutdown(it->second->fd, SHUT_RDWR);
    ::close(it->second->fd);
    it->second->fd = -1;
    it->second->closed = true;
    it->second->accepted = false;
}

bool MqttFleet::publish(const std::string& client_id, const Message& message) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = peers_.find(client_id);
        if (it == peers_.end() || !it->second->accepted) return false;
        it->second->send_publish(message);
    }
    wake();
    return true;
}

std::size_t MqttFleet::connected() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t n = 0;
    for (const auto& [id, peer] : peers_) n += peer->accepted ? 1 : 0;
    return n;
}

std::vector<Message> MqttFleet::received(const std::string& client_id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = peers_.find(client_id);
    return it == peers_.end() ? std::vector<Message>{} : it->second->received;
}

void MqttFleet::run() {
    std::vector<pollfd> fds;
    std::vector<Peer*> owners;
    while (!stopping_) {
        fds.clear();
        owners.clear();
        fds.push_back(pollfd{wake_pipe_[0], POLLIN, 0});
        owners.push_back(nullptr);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            const auto now = std::chrono::steady_clock::now();
            for (auto& [id, peer] : peers_) {
                if (peer->fd < 0) continue;
                // Keep-alive: a PINGREQ at half the interval.
                if (peer->accepted && peer->out.empty() &&
                    now - peer->last_sent > std::chrono::seconds(peer->config.keep_alive_s) / 2)
                    peer->out += packet(0xC0, "");
                short events = POLLIN;
                if (!peer->tcp_up || !peer->out.empty()) events |= POLLOUT;
                fds.push_back(pollfd{peer->fd, events, 0});
                owners.push_back(peer.get());
            }
        }
        if (::poll(fds.data(), fds.size(), 200) < 0) continue;
        if (fds[0].revents & POLLIN) {
            char buf[256];
            while (::read(wake_pipe_[0], buf, sizeof buf) > 0) {
            }
        }
        std::lock_guard<std::mutex> lock(mutex_);
        for (std::size_t i = 1; i < fds.size(); ++i) {
            Peer* peer = owners[i];
            if (peer->fd != fds[i].fd || peer->fd < 0 || !fds[i].revents) continue;  // dropped meanwhile
            if (fds[i].revents & (POLLERR | POLLHUP)) {
                ::close(peer->fd);
                peer->fd = -1;
                peer->accepted = false;
                peer->closed = true;
                continue;
            }
            if (fds[i].revents & POLLOUT) {
                peer->tcp_up = true;
                while (!peer->out.empty()) {
                    const ssize_t n = ::send(peer->fd, peer->out.data(), peer->out.size(), MSG_NOSIGNAL);
                    if (n <= 0) break;
                    peer->out.erase(0, static_cast<std::size_t>(n));
                    peer->last_sent = std::chrono::steady_clock::now();
                }
            }
            if (fds[i].revents & POLLIN) {
                char buf[16384];
                for (;;) {
                    const ssize_t n = ::recv(peer->fd, buf, sizeof buf, 0);
                    if (n > 0) {
                        peer->in.append(buf, static_cast<std::size_t>(n));
                        continue;
                    }
                    if (n == 0) {  // the broker closed it
                        ::close(peer->fd);
                        peer->fd = -1;
                        peer->accepted = false;
                        peer->closed = true;
                    }
                    break;
                }
                received_total_ += peer->parse();
            }
        }
    }
}

}  // namespace nclink::test
