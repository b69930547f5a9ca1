// The broker round-trip check: a plant's broker with its default settings
// lets Nagle's algorithm hold back a small packet until the previous one is
// acknowledged, and the peer acknowledges late (delayed ACK). nclink's own
// sockets have TCP_NODELAY but the broker's do not, and an NC-Link request
// and its response then take 40-90 ms instead of under 1 ms
// (docs/performance.md). nclink cannot change the broker; it can notice.
//
// A message a connection sends to itself does not show the delay (the broker
// writes its acknowledgement and the message in one go); a request answered
// by a second connection does, as it does for every application.
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

// What the extra time must exceed to be the broker's Nagle delay rather than
// jitter: the delayed ACK it waits for is 40 ms on Linux (at least ~20 ms
// elsewhere); a broker on the same LAN relays in well under a millisecond.
constexpr microseconds kNagleGap = milliseconds(20);

struct Arrivals {
    std::mutex mutex;
    std::condition_variable arrived;
    std::map<std::string, std::chrono::steady_clock::time_point> seen;
};

}  // namespace

std::string broker_delay_warning(const BrokerRoundTrip& measured) {
    if (measured.relayed.empty()) return {};
    const microseconds relayed = median(measured.relayed);
    const microseconds direct = median(measured.direct);
    if (relayed - 2 * direct < kNagleGap) return {};
    return fmt::format(
        "the broker delays small packets (a request answered through it takes {:.1f} ms, a message to itself "
        "{:.1f} ms): it does not set TCP_NODELAY; add `set_tcp_nodelay true` to mosquitto.conf (see "
        "docs/performance.md)",
        static_cast<double>(relayed.count()) / 1000.0, static_cast<double>(direct.count()) / 1000.0);
}

Result<BrokerRoundTrip> measure_broker_round_trip(MqttOptions options, int samples, milliseconds timeout) {
    options.last_will.reset();
    options.clean_session = true;
    const std::string base = options.client_id;
    // Under the user name when there is one: the ACL nclink-agent generates
    // grants each user nclink-rtt/<user>/# (docs/security.md), so the check
    // also runs on a locked-down broker.
    const std::string prefix = "nclink-rtt/" + (options.username.empty() ? base : options.username + "/" + base);
    const std::string topic_a = prefix + "/a";  // answers and direct messages come back here
    const std::string topic_b = prefix + "/b";  // requests to the second connection
    MqttOptions oa = options, ob = options;
    oa.client_id = base + "-rtt-a";
    ob.client_id = base + "-rtt-b";
    auto made_a = make_mqtt_transport(oa);
    if (!made_a) return std::move(made_a).error();
    auto made_b = make_mqtt_transport(ob);
    if (!made_b) return std::move(made_b).error();
    std::shared_ptr<Transport> a = std::move(made_a).value(), b = std::move(made_b).value();
    auto arrivals = std::make_shared<Arrivals>();
    a->set_message_handler([arrivals](const Message& m) {
        std::lock_guard<std::mutex> lock(arrivals->mutex);
        arrivals->seen[m.payload] = std::chrono::steady_clock::now();
        arrivals->arrived.notify_all();
    });
    // The second connection answers every request at once (QoS 1, as an
    // adapter answers), from its callback thread.
    Transport* b_raw = b.get();
    b->set_message_handler([b_raw, topic_a](const Message& m) { (void)b_raw->publish(Message{topic_a, m.payload, 1, false}); });
    if (auto r = a->subscribe({topic_a}, 1); !r) return std::move(r).error();
    if (auto r = b->subscribe({topic_b}, 1); !r) return std::move(r).error();
    struct Stop {
        std::shared_ptr<Transport> a, b;
        ~Stop() {
            a->stop(milliseconds(0));
            b->stop(milliseconds(0));
        }
    } stop{a, b};
    if (auto r = a->start(); !r) return std::move(r).error();
    if (auto r = b->start(); !r) return std::move(r).error();

    auto wait_for = [&](const std::string& tag, milliseconds limit) {
        std::unique_lock<std::mutex> lock(arrivals->mutex);
        return arrivals->arrived.wait_for(lock, limit, [&] { return arrivals->seen.count(tag) > 0; });
    };
    // Warm-up: both connections up and subscribed (a request is sent again
    // until its answer comes back).
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (int attempt = 0;; ++attempt) {
        if (a->state() == LinkState::connected && b->state() == LinkState::connected) {
            const std::string tag = "warm-up-" + std::to_string(attempt);
            (void)a->publish(Message{topic_b, tag, 1, false});
            if (wait_for(tag, milliseconds(200))) break;
        } else {
            // A broker that refused the connection (credentials, a
            // certificate) will go on refusing: no use waiting out `timeout`
            // (the caller reports the refusal itself, docs/security.md).
            if (const TransportStats s = a->stats(); s.refused)
                return make_error(ErrorCode::unavailable,
                                  fmt::format("cannot connect to {}: {}", options.broker_url, s.last_error));
            std::this_thread::sleep_for(milliseconds(10));
        }
        if (std::chrono::steady_clock::now() > deadline)
            return make_error(ErrorCode::unavailable,
                              fmt::format("cannot reach the broker at {} within {} ms", options.broker_url, timeout.count()));
    }
    auto once = [&](const std::string& tag, const std::string& topic, int qos) -> Result<microseconds> {
        const auto sent = std::chrono::steady_clock::now();
        if (auto r = a->publish(Message{topic, tag, qos, false}); !r) return std::move(r).error();
        if (!wait_for(tag, timeout))
            return make_error(ErrorCode::unavailable,
                              fmt::format("no round trip through {} within {} ms", options.broker_url, timeout.count()));
        std::lock_guard<std::mutex> lock(arrivals->mutex);
        return std::chrono::duration_cast<microseconds>(arrivals->seen[tag] - sent);
    };
    BrokerRoundTrip out;
    for (int i = 0; i < samples; ++i) {
        auto direct = once("direct-" + std::to_string(i), topic_a, 0);
        if (!direct) return std::move(direct).error();
        out.direct.push_back(*direct);
        auto relayed = once("relayed-" + std::to_string(i), topic_b, 1);
        if (!relayed) return std::move(relayed).error();
        out.relayed.push_back(*relayed);
    }
    return out;
}

}  // namespace nclink
