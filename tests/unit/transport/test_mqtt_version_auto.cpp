// mqtt_version 0 ("auto") of the libmosquitto transport against a broker
// that, as RabbitMQ 3.10 does, closes the connection of an MQTT 5 CONNECT
// without a CONNACK and accepts MQTT 3.1.1: a stand-in on a loopback port
// that records the protocol level (MQTT 3.1.2.2 / 5.0 3.1.2.2) of every
// CONNECT it reads.
#include <nclink/mqtt_transport.hpp>

#include "support/mosquitto_broker.hpp"  // free_loopback_port()
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

using namespace nclink;
using nclink::test::eventually;
using namespace std::chrono_literals;

namespace {

class Mqtt311OnlyBroker {
public:
    Mqtt311OnlyBroker() : port_(nclink::test::free_loopback_port()) {
        listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
        int yes = 1;
        ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(static_cast<uint16_t>(port_));
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::bind(listener_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
        REQUIRE(::listen(listener_, 8) == 0);
        thread_ = std::thread([this] { serve(); });
    }
    ~Mqtt311OnlyBroker() {
        stop_ = true;
        thread_.join();
        drop_client();
        ::close(listener_);
    }
    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(port_); }
    std::vector<int> levels() {
        std::lock_guard<std::mutex> lock(mutex_);
        return levels_;
    }
    /// Closes the accepted 3.1.1 connection (the client must reconnect).
    void drop_client() {
        std::lock_guard<std::mutex> lock(mutex_);
        if (client_ >= 0) ::close(client_);
        client_ = -1;
    }

private:
    void serve() {
        while (!stop_) {
            pollfd p{listener_, POLLIN, 0};
            if (::poll(&p, 1, 50) <= 0) continue;
            const int fd = ::accept(listener_, nullptr, nullptr);
            if (fd < 0) continue;
            // CONNECT: type, remaining length (< 128 here), then "\0\4MQTT" and the level.
            unsigned char head[9] = {};
            std::size_t got = 0;
            while (got < sizeof head) {
                pollfd q{fd, POLLIN, 0};
                if (::poll(&q, 1, 2000) <= 0) break;
                const ssize_t n = ::recv(fd, head + got, sizeof head - got, 0);
                if (n <= 0) break;
                got += static_cast<std::size_t>(n);
            }
            if (got < sizeof head || head[0] != 0x10) {
                ::close(fd);
                continue;
            }
            const int level = head[8];
            std::lock_guard<std::mutex> lock(mutex_);
            levels_.push_back(level);
            if (level != 4) {
                ::close(fd);  // no CONNACK: how RabbitMQ 3.10 answers MQTT 5
                continue;
            }
            const unsigned char connack[] = {0x20, 0x02, 0x00, 0x00};
            ::send(fd, connack, sizeof connack, MSG_NOSIGNAL);
            if (client_ >= 0) ::close(client_);
            client_ = fd;  // kept open (the rest of the CONNECT and PINGREQs unread)
        }
    }

    int port_;
    int listener_ = -1;
    std::atomic<bool> stop_{false};
    std::thread thread_;
    std::mutex mutex_;
    std::vector<int> levels_;
    int client_ = -1;
};

MqttOptions options_for(const std::string& url, int version) {
    MqttOptions o;
    o.broker_url = url;
    o.client_id = "auto-version";
    o.mqtt_version = version;
    o.reconnect_min = 20ms;
    o.reconnect_max = 100ms;
    return o;
}

}  // namespace

TEST_CASE("mqtt_version auto falls back to MQTT 3.1.1 when the broker closes a 5 CONNECT, and keeps it") {
    Mqtt311OnlyBroker broker;
    auto made = make_mqtt_transport(options_for(broker.url(), 0));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5, 4});

    // A reconnection speaks the level that was accepted, at once.
    broker.drop_client();
    REQUIRE(eventually([&] { return broker.levels().size() == 3 && transport.state() == LinkState::connected; }, 10s));
    CHECK(broker.levels() == std::vector<int>{5, 4, 4});
    transport.stop(0ms);
}

TEST_CASE("mqtt_version 5 stays 5 with a broker that refuses it") {
    Mqtt311OnlyBroker broker;
    auto made = make_mqtt_transport(options_for(broker.url(), 5));
    REQUIRE(made);
    auto& transport = **made;
    REQUIRE(transport.start());
    REQUIRE(eventually([&] { return broker.levels().size() >= 3; }, 10s));
    CHECK(transport.state() != LinkState::connected);
    for (int level : broker.levels()) CHECK(level == 5);
    transport.stop(0ms);
}
