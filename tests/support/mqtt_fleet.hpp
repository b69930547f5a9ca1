// Many light MQTT 3.1.1 clients on one thread, for tests and benchmarks that
// need hundreds or thousands of terminals on a real broker: a paho client per
// terminal would cost threads and memory the test is not about. Each client
// connects (optionally with a last will), subscribes, publishes what it was
// given at connect, acknowledges QoS 1 messages it receives and keeps what
// arrived. Only the parts of MQTT 3.1.1 these peers need (QoS 0/1, no
// session resumption).
#pragma once

#include <nclink/transport.hpp>

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace nclink::test {

struct FleetClient {
    std::string client_id;
    std::vector<std::string> subscriptions;  ///< QoS 1, subscribed right after CONNACK
    std::vector<Message> on_connect;         ///< published (in order) after the subscriptions
    std::optional<Message> will;
    int keep_alive_s = 60;
};

class MqttFleet {
public:
    explicit MqttFleet(int port);
    ~MqttFleet();  ///< closes every socket (no DISCONNECT: wills fire)
    MqttFleet(const MqttFleet&) = delete;
    MqttFleet& operator=(const MqttFleet&) = delete;

    /// Starts connecting a client. Thread-safe.
    void add(FleetClient client);
    /// Closes a client's socket without DISCONNECT (its will fires). Thread-safe.
    void drop(const std::string& client_id);
    /// Publishes from a connected client. Thread-safe; false when not connected.
    bool publish(const std::string& client_id, const Message& message);

    /// Clients whose CONNACK accepted them.
    std::size_t connected() const;
    /// Messages received by a client, in arrival order.
    std::vector<Message> received(const std::string& client_id) const;
    /// Messages received by all clients together.
    std::uint64_t received_total() const { return received_total_; }

private:
    struct Peer;
    void run();
    void wake();

    const int port_;
    mutable std::mutex mutex_;
    std::map<std::string, std::unique_ptr<Peer>> peers_;
    std::atomic<std::uint64_t> received_total_{0};
    std::atomic<bool> stopping_{false};
    int wake_pipe_[2] = {-1, -1};
    std::thread thread_;
};

}  // namespace nclink::test
