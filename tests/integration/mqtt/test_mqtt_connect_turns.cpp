// A gateway's connections take turns to connect (transport/connect_turns.hpp):
// against a listener that accepts and never answers a CONNECT, at most the
// limit are open at once, and each failed attempt passes the turn on.
#include <nclink/mqtt_transport.hpp>

#include "support/loopback_listener.hpp"
#include "support/wait.hpp"
#include "transport/mosquitto_transport.hpp"
#include "transport/mqtt_loop.hpp"

#include <catch2/catch.hpp>

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

using namespace nclink;
using nclink::test::eventually;

namespace {

// Accepts TCP connections on a free 127.0.0.1 port, reads what they send and
// answers nothing: a broker that never sends CONNACK.
class SilentListener {
public:
    SilentListener() : listener_(0, 64, "silent listener") {
        thread_ = std::thread([this] { run(); });
    }
    ~SilentListener() {
        stop_ = true;
        thread_.join();
    }
    int port() const { return listener_.port(); }
    int accepted() const { return accepted_; }
    int most_open() const { return most_open_; }

private:
    void run() {
        std::vector<int> open;
        while (!stop_) {
            std::vector<pollfd> p{{listener_.fd(), POLLIN, 0}};
            for (int c : open) p.push_back({c, POLLIN, 0});
            if (::poll(p.data(), p.size(), 20) <= 0) continue;
            if (p[0].revents & POLLIN) {
                const int c = ::accept4(listener_.fd(), nullptr, nullptr, SOCK_CLOEXEC);
                if (c >= 0) {
                    open.push_back(c);
                    ++accepted_;
                }
            }
            for (std::size_t i = 1; i < p.size(); ++i) {
                if (!(p[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
                char buffer[512];
                if (::read(p[i].fd, buffer, sizeof buffer) <= 0) {
                    ::close(p[i].fd);
                    open.erase(std::find(open.begin(), open.end(), p[i].fd));
                }
            }
            most_open_ = std::max<int>(most_open_, static_cast<int>(open.size()));
        }
        for (int c : open) ::close(c);
    }

    nclink::test::LoopbackListener listener_;
    std::atomic<bool> stop_{false};
    std::atomic<int> accepted_{0}, most_open_{0};
    std::thread thread_;
};

}  // namespace

TEST_CASE("connections on a shared loop take turns to connect: at most the limit wait for a CONNACK") {
    SilentListener broker;
    auto loop = std::make_shared<transport_detail::MqttLoop>(Logger(), std::chrono::milliseconds(20), 2);
    std::vector<std::unique_ptr<Transport>> machines;
    for (int i = 0; i < 6; ++i) {
        MqttOptions o;
        o.broker_url = "tcp://127.0.0.1:" + std::to_string(broker.port());
        o.client_id = "nclink-test-turns-" + std::to_string(i);
        o.connect_timeout = std::chrono::milliseconds(300);
        o.reconnect_min = std::chrono::milliseconds(50);
        o.reconnect_max = std::chrono::milliseconds(50);
        auto made = transport_detail::make_mosquitto_transport(o, Logger(), loop);
        REQUIRE(made.ok());
        machines.push_back(std::move(made).value());
        REQUIRE(machines.back()->start().ok());
    }
    // Two connect; the other four wait without a socket. Each attempt ends
    // in its connect timeout and hands the turn to the next in line, so
    // every machine gets to try, never more than two at once.
    REQUIRE(eventually([&] { return broker.accepted() >= 8; }, std::chrono::seconds(10)));
    CHECK(broker.most_open() <= 2);
    // Stopped machines leave the line (read once every removal is done:
    // remove() returns after the loop thread has dropped the member).
    for (auto& m : machines) m->stop(std::chrono::milliseconds(0));
    CHECK(loop->connect_waiting() == 0);
}
