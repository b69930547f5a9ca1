// The broker round-trip check: a plant's broker with its default settings
// delays every second small packet by the peer's delayed ACK (Nagle's
// algorithm); nclink's own sockets have TCP_NODELAY but the broker's do not,
// and a QoS 1 request/response then costs ~40-90 ms instead of under 1 ms
// (docs/performance.md). nclink cannot change the broker; it can notice.
#include <nclink/mqtt_transport.hpp>

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>

#include <fmt/format.h>

namespace nclink {

namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

microseconds median(std::vector<microseconds> v) {
    if (v.empty()) return microseconds(0);
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// What the delay must exceed to be the broker's Nagle delay rather than
// jitter: the delayed ACK it waits for is 40 ms on Linux (at least ~20 ms
// elsewhere), a fast broker on a LAN answers in well under a millisecond.
constexpr microseconds kNagleGap = milliseconds(20);

struct Echo {
    std::mutex mutex;
    std::condition_variable arrived;
    std::map<std::string, std::chrono::steady_clock::time_point> seen;
};

}  // namespace

std::string broker_delay_warning(const BrokerRoundTrip& measured) {
    if (measured.qos1.empty()) return {};
    const microseconds q1 = median(measured.qos1);
    const microseconds q0 = median(measured.qos0);
    if (q1 < kNagleGap || q1 - q0 < kNagleGap) return {};
    return fmt::format(
        "the broker delays QoS 1 messages ({:.1f} ms round trip against {:.1f} ms at QoS 0): it does not set "
        "TCP_NODELAY; add `set_tcp_nodelay true` to mosquitto.conf (see docs/performance.md)",
        static_cast<double>(q1.count()) / 1000.0, static_cast<double>(q0.count()) / 1000.0);
}

Result<BrokerRoundTrip> measure_broker_round_trip(MqttOptions options, int samples, milliseconds timeout) {
    options.client_id += "-rtt";
    options.last_will.reset();
    options.clean_session = true;
    const std::string topic = "nclink-rtt/" + options.client_id;
    auto made = make_mqtt_transport(options);
    if (!made) return std::move(made).error();
    auto transport = std::move(made).value();
    auto echo = std::make_shared<Echo>();
    transport->set_message_handler([echo](const Message& m) {
        std::lock_guard<std::mutex> lock(echo->mutex);
        echo->seen[m.payload] = std::chrono::steady_clock::now();
        echo->arrived.notify_all();
    });
    if (auto r = transport->subscribe({topic}, 1); !r) return std::move(r).error();
    if (auto r = transport->start(); !r) return std::move(r).error();
    struct Stop {
        Transport& t;
        ~Stop() { t.stop(milliseconds(0)); }
    } stop{*transport};

    // One message there and back; the time from publish to arrival.
    auto once = [&](const std::string& tag, int qos) -> Result<microseconds> {
        const auto sent = std::chrono::steady_clock::now();
        if (auto r = transport->publish(Message{topic, tag, qos, false}); !r) return std::move(r).error();
        std::unique_lock<std::mutex> lock(echo->mutex);
        if (!echo->arrived.wait_for(lock, timeout, [&] { return echo->seen.count(tag) > 0; }))
            return make_error(ErrorCode::unavailable,
                              fmt::format("no round trip through {} within {} ms", options.broker_url, timeout.count()));
        return std::chrono::duration_cast<microseconds>(echo->seen[tag] - sent);
    };
    // The warm-up waits out the connection and the subscription (the
    // message is published again until the subscription is in place).
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (int attempt = 0;; ++attempt) {
        if (transport->state() == LinkState::connected) {
            const std::string tag = "warm-up-" + std::to_string(attempt);
            (void)transport->publish(Message{topic, tag, 1, false});
            std::unique_lock<std::mutex> lock(echo->mutex);
            if (echo->arrived.wait_for(lock, milliseconds(200), [&] { return echo->seen.count(tag) > 0; })) break;
        } else {
            std::this_thread::sleep_for(milliseconds(10));
        }
        if (std::chrono::steady_clock::now() > deadline)
            return make_error(ErrorCode::unavailable,
                              fmt::format("cannot reach the broker at {} within {} ms", options.broker_url,
                                          timeout.count()));
    }
    BrokerRoundTrip out;
    for (int i = 0; i < samples; ++i) {
        auto q0 = once("q0-" + std::to_string(i), 0);
        if (!q0) return std::move(q0).error();
        out.qos0.push_back(*q0);
        auto q1 = once("q1-" + std::to_string(i), 1);
        if (!q1) return std::move(q1).error();
        out.qos1.push_back(*q1);
    }
    return out;
}

}  // namespace nclink
