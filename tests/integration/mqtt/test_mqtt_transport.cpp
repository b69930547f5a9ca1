// MqttTransport against a real mosquitto on a free 127.0.0.1 port.
#include <nclink/mqtt_transport.hpp>
#include <nclink/paho_transport.hpp>

#include "support/ack_dropping_proxy.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/test_pki.hpp"
#include "support/inbox.hpp"
#include "support/wait.hpp"
#include "transport/mosquitto_transport.hpp"
#include "transport/mqtt_loop.hpp"
#include "transport/tcp_nodelay.hpp"

#include <catch2/catch.hpp>

#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <thread>
#include <filesystem>
#include <fstream>
#include <map>
#include <cstdlib>
#include <mutex>
#include <set>
#include <string>
#include <vector>

using namespace nclink;
using nclink::test::eventually;
using nclink::test::Inbox;
using nclink::test::MosquittoBroker;
using nclink::test::MosquittoOptions;

namespace {

Logger o_logger;  // set NCLINK_TEST_LOG=1 to see the transports' logs

MqttOptions options_for(const MosquittoBroker& broker, const std::string& id) {
    MqttOptions o;
    o.broker_url = broker.url();
    o.client_id = id;
    o.reconnect_min = std::chrono::milliseconds(50);
    o.reconnect_max = std::chrono::milliseconds(500);
    if (std::getenv("NCLINK_TEST_LOG")) o_logger = Logger(stderr_sink(), LogLevel::debug);
    return o;
}

// Which client the tests marked GENERATE_CLIENT() run on: libmosquitto with
// a loop of its own (make_mqtt_transport(): libnclink, single adapters),
// libmosquitto on a shared loop (gateways), paho (make_paho_transport():
// libnclink-plant, the client and the agent). All keep one contract.
enum class Client { own_loop, shared_loop, paho };
Client g_client = Client::own_loop;
const char* client_name(Client c) {
    return c == Client::paho          ? "paho"
           : c == Client::shared_loop ? "libmosquitto on a shared loop"
                                      : "libmosquitto on its own loop";
}
#define GENERATE_CLIENT()                                                     \
    g_client = GENERATE(Client::own_loop, Client::shared_loop, Client::paho); \
    INFO(client_name(g_client))

// One loop for the transports alive at once, as in a gateway.
std::shared_ptr<transport_detail::MqttLoop> shared_loop() {
    static std::weak_ptr<transport_detail::MqttLoop> current;
    auto loop = current.lock();
    if (!loop) {
        loop = std::make_shared<transport_detail::MqttLoop>(o_logger);
        current = loop;
    }
    return loop;
}

Result<std::unique_ptr<Transport>> make_transport(MqttOptions o, Logger logger = o_logger) {
    if (g_client == Client::shared_loop)
        return transport_detail::make_mosquitto_transport(std::move(o), std::move(logger), shared_loop());
    if (g_client == Client::paho) return make_paho_transport(std::move(o), std::move(logger));
    return make_mqtt_transport(std::move(o), std::move(logger));
}

std::unique_ptr<Transport> connect(MqttOptions o) {
    auto made = make_transport(std::move(o));
    REQUIRE(made.ok());
    return std::move(made).value();
}

std::set<int> broker_fds(int port) {
    std::set<int> fds;
    for (const auto& s : transport_detail::sockets_connected_to("127.0.0.1", port)) fds.insert(s.fd);
    return fds;
}

}  // namespace

TEST_CASE("publish and subscribe through mosquitto, in order, with TCP_NODELAY on the socket") {
    GENERATE_CLIENT();
    MosquittoBroker broker;
    auto pub = connect(options_for(broker, "nclink-test-pub"));
    auto sub = connect(options_for(broker, "nclink-test-sub"));
    Inbox inbox;
    inbox.attach(*sub);
    REQUIRE(sub->start().ok());
    REQUIRE(sub->subscribe({"Sample/dev/#"}, 1).ok());
    REQUIRE(eventually([&] { return sub->state() == LinkState::connected; }));
    REQUIRE(pub->start().ok());
    REQUIRE(eventually([&] { return pub->state() == LinkState::connected; }));
    // The subscription is acknowledged asynchronously: wait until a probe arrives.
    REQUIRE(eventually([&] {
        (void)pub->publish({"Sample/dev/probe", "probe", 1, false});
        return eventually([&] { return inbox.count() > 0; }, std::chrono::milliseconds(200));
    }));
    const std::size_t base = inbox.count();
    // One QoS per stream: MQTT orders messages per QoS level only.
    for (int i = 0; i < 1000; ++i) REQUIRE(pub->publish({"Sample/dev/ch", std::to_string(i), 1, false}).ok());
    REQUIRE(eventually([&] { return inbox.count() >= base + 1000; }));
    auto got = inbox.payloads();
    std::vector<std::string> data(got.end() - 1000, got.end());
    for (int i = 0; i < 1000; ++i) REQUIRE(data[static_cast<std::size_t>(i)] == std::to_string(i));

    // Every socket this process has to the broker carries TCP_NODELAY.
    CHECK(pub->stats().tcp_nodelay_sockets >= 1);
    const auto sockets = transport_detail::sockets_connected_to("127.0.0.1", broker.port());
    REQUIRE(sockets.size() >= 2);
    for (const auto& s : sockets) CHECK(s.nodelay);
    pub->stop();
    sub->stop();
}

TEST_CASE("without the option no TCP_NODELAY is set (the test above can fail)") {
    GENERATE_CLIENT();
    MosquittoBroker broker;
    auto o = options_for(broker, "nclink-test-nagle");
    o.tcp_nodelay = false;
    auto t = connect(o);
    REQUIRE(t->start().ok());
    REQUIRE(eventually([&] { return t->state() == LinkState::connected; }));
    const auto sockets = transport_detail::sockets_connected_to("127.0.0.1", broker.port());
    REQUIRE(sockets.size() == 1);
    CHECK_FALSE(sockets[0].nodelay);
    CHECK(t->stats().tcp_nodelay_sockets == 0);
    t->stop();
}

TEST_CASE("messages published while the broker restarts are delivered after it, in order") {
    GENERATE_CLIENT();
    // What is tested is the publisher's buffer: kept while the broker is
    // away, sent in order after it. The subscriber reconnects (and
    // resubscribes) within ~50 ms of the restart; the publisher waits 1.5 s
    // before its first retry, so nothing is re-sent before someone listens.
    MosquittoBroker broker;
    auto sub = connect(options_for(broker, "nclink-test-sub-restart"));
    Inbox inbox;
    inbox.attach(*sub);
    REQUIRE(sub->start().ok());
    REQUIRE(sub->subscribe({"Event/dev/app"}, 1).ok());
    auto pub_options = options_for(broker, "nclink-test-pub-restart");
    pub_options.reconnect_min = std::chrono::milliseconds(1500);
    pub_options.reconnect_max = std::chrono::milliseconds(1500);
    auto pub = connect(pub_options);
    REQUIRE(pub->start().ok());
    REQUIRE(eventually([&] { return pub->state() == LinkState::connected && sub->state() == LinkState::connected; }));
    REQUIRE(eventually([&] {
        (void)pub->publish({"Event/dev/app", "probe", 1, false});
        return eventually([&] { return inbox.count() > 0; }, std::chrono::milliseconds(200));
    }));
    REQUIRE(pub->flush(std::chrono::seconds(5)));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // stray probes land
    const std::size_t base = inbox.count();

    broker.stop();
    REQUIRE(eventually([&] { return pub->state() != LinkState::connected; }));
    for (int i = 0; i < 50; ++i) REQUIRE(pub->publish({"Event/dev/app", "e" + std::to_string(i), 1, false}).ok());
    CHECK(pub->stats().buffered + pub->stats().in_flight == 50);
    // The publisher's first (immediate) reconnect attempt fails against the
    // stopped broker; it is then in its 1.5 s back-off when the broker returns.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    broker.start();

    REQUIRE(eventually([&] { return inbox.count() >= base + 50; }, std::chrono::seconds(20)));
    auto got = inbox.payloads();
    std::vector<std::string> after(got.begin() + static_cast<std::ptrdiff_t>(base), got.end());
    // At-least-once: a message in flight at the cut may arrive twice, but
    // the sequence without repeats is complete and in order.
    std::vector<std::string> unique;
    for (const auto& p : after)
        if (unique.empty() || unique.back() != p) unique.push_back(p);
    REQUIRE(unique.size() == 50);
    for (int i = 0; i < 50; ++i) CHECK(unique[static_cast<std::size_t>(i)] == "e" + std::to_string(i));
    CHECK(pub->stats().dropped == 0);
    CHECK(pub->stats().connects >= 2);
}

TEST_CASE("a persistent broker keeps an absent subscriber's session and queued messages over a restart") {
    GENERATE_CLIENT();
    // What docs/delivery.md's table rests on, and what every persistence
    // test assumes of the test broker: it really saves (started as root it
    // runs as its own user, who must own the directory it saves in).
    MosquittoOptions persistent;
    persistent.persistent = true;
    MosquittoBroker broker(persistent);
    auto sub_options = options_for(broker, "nclink-test-sub-persistent");
    sub_options.clean_session = false;
    {
        auto sub = connect(sub_options);
        REQUIRE(sub->start().ok());
        REQUIRE(sub->subscribe({"Event/dev/app"}, 1).ok());
        REQUIRE(eventually([&] { return sub->state() == LinkState::connected; }));
        std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the SUBACK
        sub->stop();
    }
    auto pub = connect(options_for(broker, "nclink-test-pub-persistent"));
    REQUIRE(pub->start().ok());
    for (int i = 0; i < 20; ++i) REQUIRE(pub->publish({"Event/dev/app", "q" + std::to_string(i), 1, false}).ok());
    REQUIRE(pub->flush(std::chrono::seconds(10)));
    pub->stop();
    broker.restart();
    // The same session, not subscribing again: only the broker's saved
    // session can bring the messages.
    auto back = connect(sub_options);
    Inbox inbox;
    inbox.attach(*back);
    REQUIRE(back->start().ok());
    REQUIRE(eventually([&] { return inbox.count() >= 20; }, std::chrono::seconds(10)));
    const auto got = inbox.payloads();
    for (int i = 0; i < 20; ++i) CHECK(got[static_cast<std::size_t>(i)] == "q" + std::to_string(i));
    // Reconnected after another restart, the session is still there: nothing to warn about.
    broker.restart();
    REQUIRE(eventually([&] { return back->stats().connects >= 2 && back->state() == LinkState::connected; },
                       std::chrono::seconds(10)));
    CHECK(back->stats().sessions_lost == 0);
}

TEST_CASE("a persistent session the broker forgot over a restart is counted and logged, never silent") {
    GENERATE_CLIENT();
    MosquittoBroker broker;  // no persistence: a restart forgets every session
    auto options = options_for(broker, "nclink-test-sub-forgotten");
    options.clean_session = false;
    std::vector<std::string> warnings;
    std::mutex warnings_mutex;
    auto made = make_transport(options, Logger(
                                            [&](LogLevel level, std::string_view message) {
                                                if (level != LogLevel::warn) return;
                                                std::lock_guard<std::mutex> lock(warnings_mutex);
                                                warnings.emplace_back(message);
                                            },
                                            LogLevel::debug));
    REQUIRE(made.ok());
    auto sub = std::move(made).value();
    REQUIRE(sub->start().ok());
    REQUIRE(eventually([&] { return sub->state() == LinkState::connected; }));
    CHECK(sub->stats().sessions_lost == 0);  // a first connection has no session to lose
    broker.restart();
    REQUIRE(
        eventually([&] { return sub->stats().connects >= 2 && sub->state() == LinkState::connected; }, std::chrono::seconds(10)));
    // Counted by the supervisor once the CONNACK's token is back, a moment
    // after paho's connected callback: wait for it, it must become 1.
    CHECK(eventually([&] { return sub->stats().sessions_lost == 1; }, std::chrono::seconds(5)));
    CHECK(sub->stats().sessions_lost == 1);
    // Logged right after it is counted, on the supervisor's thread: wait
    // for the line too (under TSan the test read the log in between).
    const auto warned = [&] {
        std::lock_guard<std::mutex> lock(warnings_mutex);
        return std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) {
            return w.find("kept no session for client id 'nclink-test-sub-forgotten'") != std::string::npos;
        });
    };
    CHECK(eventually([&] { return warned() >= 1; }, std::chrono::seconds(5)));
    CHECK(warned() == 1);
}

TEST_CASE("an abrupt disconnect publishes the last will, the transport reconnects") {
    GENERATE_CLIENT();
    MosquittoBroker broker;
    auto adapter_options = options_for(broker, "nclink-test-adapter");
    adapter_options.last_will = Message{"Notify/State/dev1", R"({"tid":"dev1","state":"offline"})", 1, true};
    auto adapter = connect(adapter_options);
    REQUIRE(adapter->start().ok());
    REQUIRE(eventually([&] { return adapter->state() == LinkState::connected; }));
    const auto adapter_sockets = broker_fds(broker.port());
    REQUIRE(adapter_sockets.size() == 1);

    auto app = connect(options_for(broker, "nclink-test-app"));
    Inbox inbox;
    inbox.attach(*app);
    REQUIRE(app->start().ok());
    REQUIRE(app->subscribe({"Notify/State/+"}, 1).ok());
    REQUIRE(eventually([&] { return app->state() == LinkState::connected; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // let SUBACK land before the cut

    ::shutdown(*adapter_sockets.begin(), SHUT_RDWR);  // the network "fails" under paho
    REQUIRE(eventually([&] { return inbox.count() >= 1; }));
    {
        std::lock_guard<std::mutex> lock(inbox.mutex);
        CHECK(inbox.messages[0].topic == "Notify/State/dev1");
        CHECK(inbox.messages[0].payload == R"({"tid":"dev1","state":"offline"})");
    }
    REQUIRE(eventually([&] { return adapter->stats().connects >= 2 && adapter->state() == LinkState::connected; }));
    adapter->stop();
    app->stop();
}

// paho fails every unacknowledged publish from inside its client's destroy;
// that callback once ran on the transport's outbox after the outbox was gone
// (member order), corrupting the heap at shutdown. Under the ASan preset this
// test reports the use after free without the fix; here it must not crash.
TEST_CASE("a transport destroyed with QoS 1 messages unacknowledged by a hung broker shuts down cleanly") {
    GENERATE_CLIENT();
    MosquittoBroker broker;
    auto t = connect(options_for(broker, "nclink-test-hung"));
    REQUIRE(t->start().ok());
    REQUIRE(eventually([&] { return t->state() == LinkState::connected; }));
    broker.freeze();
    for (int i = 0; i < 20; ++i) REQUIRE(t->publish({"x/hung", std::to_string(i), 1, false}).ok());
    REQUIRE(eventually([&] { return t->stats().in_flight == 20; }));
    CHECK(t->stats().published == 0);
    t.reset();  // stop() and destroy with all 20 in flight
    broker.thaw();

    // The process goes on serving: a new transport on the same broker works.
    auto again = connect(options_for(broker, "nclink-test-hung"));
    REQUIRE(again->start().ok());
    REQUIRE(eventually([&] { return again->state() == LinkState::connected; }));
    REQUIRE(again->publish({"x/hung", "after", 1, false}).ok());
    CHECK(again->flush(std::chrono::seconds(5)));
    again->stop();
}

// docs/delivery.md "A link that stops acknowledging": a link whose broker
// keeps talking (requests come in, keep-alive is answered) but whose
// in-flight window is never acknowledged again. Keep-alive cannot see it;
// the ack watchdog (transport/ack_watchdog.hpp) takes the link for dead,
// reconnects and sends the unacknowledged messages again.
// libmosquitto only (the paho transport has no such watchdog).
TEST_CASE("a link that stops acknowledging while it still delivers is dropped, remade, and nothing is lost") {
    GENERATE_CLIENT();
    MosquittoBroker broker;
    test::AckDroppingProxy proxy(broker.port());

    auto watcher = connect(options_for(broker, "nclink-test-watcher"));
    Inbox seen;
    seen.attach(*watcher);
    REQUIRE(watcher->start().ok());
    REQUIRE(watcher->subscribe({"x/acked/#"}, 1).ok());
    REQUIRE(eventually([&] { return watcher->state() == LinkState::connected; }));

    auto o = options_for(broker, "nclink-test-unacked");
    o.broker_url = proxy.url();
    o.ack_timeout = std::chrono::milliseconds(1500);
    auto t = connect(o);
    Inbox in;
    in.attach(*t);
    REQUIRE(t->start().ok());
    REQUIRE(t->subscribe({"x/in"}, 0).ok());
    REQUIRE(eventually([&] { return t->state() == LinkState::connected; }));
    REQUIRE(t->publish({"x/acked/first", "0", 1, false}).ok());
    REQUIRE(t->flush(std::chrono::seconds(5)));

    proxy.drop_acks_now();
    // The broker goes on delivering to the client: the link looks alive.
    struct Talker {  // joined however the test ends
        std::atomic<bool> talking{true};
        std::thread thread;
        ~Talker() {
            talking = false;
            if (thread.joinable()) thread.join();
        }
    } talker;
    talker.thread = std::thread([&] {
        while (talker.talking) {
            (void)watcher->publish({"x/in", "ping", 0, false});
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    });
    for (int i = 1; i <= 20; ++i) REQUIRE(t->publish({"x/acked/" + std::to_string(i), std::to_string(i), 1, false}).ok());
    REQUIRE(eventually([&] { return proxy.acks_dropped() >= 20; }));
    CHECK(t->stats().in_flight == 20);
    const auto received_before = t->stats().received;

    // Without the watchdog the window stays full for good (keep-alive is answered).
    REQUIRE(eventually([&] { return t->stats().published == 21 && t->stats().in_flight == 0; }, std::chrono::seconds(15)));
    CHECK(t->stats().stalled_links == 1);
    CHECK(t->stats().connects == 2);
    CHECK(t->stats().received > received_before);  // it was never deaf
    CHECK(proxy.connections() == 2);
    // Everything reached the broker (at least once: sent twice when its first PUBACK was lost).
    REQUIRE(eventually([&] {
        auto p = seen.payloads();
        std::set<std::string> got(p.begin(), p.end());
        return got.size() == 21;
    }));
    t->stop();
    watcher->stop();
}

TEST_CASE("a broker frozen longer than the ack timeout: the link is remade after it resumes and nothing is lost") {
    GENERATE_CLIENT();
    MosquittoBroker broker;
    auto watcher = connect(options_for(broker, "nclink-test-frozen-watcher"));
    Inbox seen;
    seen.attach(*watcher);
    REQUIRE(watcher->start().ok());
    REQUIRE(watcher->subscribe({"x/frozen/#"}, 1).ok());
    REQUIRE(eventually([&] { return watcher->state() == LinkState::connected; }));
    auto o = options_for(broker, "nclink-test-frozen");
    o.ack_timeout = std::chrono::milliseconds(1500);
    o.connect_timeout = std::chrono::milliseconds(1000);
    auto t = connect(o);
    REQUIRE(t->start().ok());
    REQUIRE(eventually([&] { return t->state() == LinkState::connected; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the watcher's SUBACK has landed

    broker.freeze();
    for (int i = 0; i < 30; ++i) REQUIRE(t->publish({"x/frozen/" + std::to_string(i), std::to_string(i), 1, false}).ok());
    REQUIRE(eventually([&] { return t->stats().stalled_links >= 1; }));
    CHECK(t->stats().published == 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // reconnection attempts meet the frozen broker too
    broker.thaw();

    REQUIRE(eventually([&] { return t->state() == LinkState::connected && t->stats().connects >= 2; }, std::chrono::seconds(20)));
    CHECK(t->flush(std::chrono::seconds(10)));
    CHECK(t->stats().published == 30);
    CHECK(t->stats().in_flight == 0);
    // Every message reached the subscriber (some perhaps twice: the broker
    // read the first copies from the dropped connection after it resumed).
    REQUIRE(eventually([&] {
        auto p = seen.payloads();
        return std::set<std::string>(p.begin(), p.end()).size() == 30;
    }));
    t->stop();
    watcher->stop();
}

TEST_CASE("a transport started before its broker connects when the broker comes up") {
    GENERATE_CLIENT();
    MosquittoOptions bo;
    bo.start = false;
    MosquittoBroker broker(bo);
    auto t = connect(options_for(broker, "nclink-test-early"));
    std::vector<LinkState> states;
    std::mutex mutex;
    t->set_state_handler([&](LinkState s, std::string_view) {
        std::lock_guard<std::mutex> lock(mutex);
        states.push_back(s);
    });
    REQUIRE(t->start().ok());
    REQUIRE(t->publish({"x/y", "queued before the broker exists", 1, false}).ok());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    CHECK(t->state() != LinkState::connected);
    broker.start();
    REQUIRE(eventually([&] { return t->state() == LinkState::connected; }));
    REQUIRE(t->flush(std::chrono::seconds(5)));
    CHECK(t->stats().published == 1);
    t->stop();
    std::lock_guard<std::mutex> lock(mutex);
    CHECK(std::find(states.begin(), states.end(), LinkState::connecting) != states.end());
}

TEST_CASE("unusable options are refused with a clear error") {
    MqttOptions o;
    o.client_id = "";
    auto r = make_mqtt_transport(o);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::parameter_missing);
    o.client_id = "x";
    o.broker_url = "not a url";
    r = make_mqtt_transport(o);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::value_type);
    o.broker_url = "tcp://127.0.0.1:99999";
    CHECK_FALSE(make_mqtt_transport(o).ok());
}

TEST_CASE("the transport of libnclink refuses WebSocket brokers and names the plant library's, which takes them") {
    MqttOptions o;
    o.client_id = "x";
    for (const char* url : {"ws://127.0.0.1:9001/mqtt", "wss://broker.plant/mqtt"}) {
        o.broker_url = url;
        auto r = make_mqtt_transport(o);
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().code == ErrorCode::value_type);
        CHECK(r.error().message.find("libnclink-plant") != std::string::npos);
        CHECK(make_paho_transport(o).ok());  // connects nowhere until started
    }
    o.broker_url = "ssl://127.0.0.1:8883";
    CHECK(make_mqtt_transport(o).ok());  // this build has TLS (NCLINK_WITH_TLS, docs/building.md)
}

TEST_CASE("broker URLs parse with default ports") {
    std::string host, scheme;
    int port = 0;
    REQUIRE(transport_detail::parse_broker_url("tcp://127.0.0.1:1884", host, port, scheme));
    CHECK((host == "127.0.0.1" && port == 1884 && scheme == "tcp"));
    REQUIRE(transport_detail::parse_broker_url("ssl://broker.plant", host, port, scheme));
    CHECK((host == "broker.plant" && port == 8883));
    REQUIRE(transport_detail::parse_broker_url("ws://[::1]:9001/mqtt", host, port, scheme));
    CHECK((host == "::1" && port == 9001));
    CHECK_FALSE(transport_detail::parse_broker_url("ftp://x", host, port, scheme));
    CHECK_FALSE(transport_detail::parse_broker_url("tcp://:1883", host, port, scheme));
}

TEST_CASE("broker round trip: measured through a real broker on connections of its own") {
    nclink::test::MosquittoBroker broker;
    nclink::MqttOptions options;
    options.broker_url = broker.url();
    options.client_id = "rtt-check";
    const auto measured = nclink::measure_broker_round_trip(options, 3, std::chrono::seconds(10));
    REQUIRE(measured.ok());
    CHECK(measured->direct.size() == 3);
    CHECK(measured->relayed.size() == 3);
    // The warning depends on timing; what it decides is tested with injected
    // measurements (tests/unit/transport). Shown here for the record.
    INFO("warning: " << nclink::broker_delay_warning(*measured));
    CHECK(true);
}

TEST_CASE("broker round trip: an unreachable broker is an error, not a hang") {
    nclink::MqttOptions options;
    options.broker_url = "tcp://127.0.0.1:" + std::to_string(nclink::test::free_loopback_port());
    options.client_id = "rtt-nobody";
    const auto measured = nclink::measure_broker_round_trip(options, 1, std::chrono::milliseconds(500));
    REQUIRE_FALSE(measured.ok());
    CHECK(measured.error().code == nclink::ErrorCode::unavailable);
}

namespace {
int threads_named(const std::string& name) {
    int n = 0;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
        std::ifstream comm(entry.path() / "comm");
        std::string line;
        if (std::getline(comm, line) && line == name) ++n;
    }
    return n;
}
}  // namespace

TEST_CASE("two hundred connections share one I/O thread and each gets exactly its own messages") {
    g_client = Client::shared_loop;
    MosquittoBroker broker;
    constexpr int kMachines = 200;
    // Eight at a time wait for their CONNACK (connect_turns.hpp): each
    // CONNACK passes the turn on, so all 200 connect.
    auto loop = std::make_shared<transport_detail::MqttLoop>(o_logger, std::chrono::milliseconds(100), 8);
    std::vector<std::unique_ptr<Transport>> machines;
    for (int i = 0; i < kMachines; ++i) {
        auto o = options_for(broker, "nclink-test-gw-" + std::to_string(i));
        o.last_will = Message{"Notify/State/gw-" + std::to_string(i), "offline", 1, false};
        auto made = transport_detail::make_mosquitto_transport(o, o_logger, loop);
        REQUIRE(made.ok());
        machines.push_back(std::move(made).value());
        // Each machine answers on its own connection what it received on it.
        Transport* self = machines.back().get();
        self->set_message_handler([self, i](const Message& m) {
            (void)self->publish({"Query/Response/gw-" + std::to_string(i) + "/app", m.payload, 1, false});
        });
        REQUIRE(machines.back()->subscribe({"Query/Request/gw-" + std::to_string(i) + "/+"}, 1).ok());
        REQUIRE(machines.back()->start().ok());
    }
    CHECK(threads_named("nclink-mqtt-io") >= 1);
    REQUIRE(eventually(
        [&] {
            return std::all_of(machines.begin(), machines.end(), [](const auto& t) { return t->state() == LinkState::connected; });
        },
        std::chrono::seconds(20)));

    auto app = connect(options_for(broker, "nclink-test-gw-app"));
    Inbox replies;
    replies.attach(*app);
    REQUIRE(app->subscribe({"Query/Response/+/app", "Notify/State/+"}, 1).ok());
    REQUIRE(app->start().ok());
    REQUIRE(eventually([&] { return app->state() == LinkState::connected; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // SUBACKs

    for (int round = 0; round < 5; ++round)
        for (int i = 0; i < kMachines; ++i)
            REQUIRE(app->publish({"Query/Request/gw-" + std::to_string(i) + "/app",
                                  std::to_string(i) + ":" + std::to_string(round), 1, false})
                        .ok());
    REQUIRE(eventually([&] { return replies.count() >= 5 * kMachines; }, std::chrono::seconds(20)));
    {
        std::lock_guard<std::mutex> lock(replies.mutex);
        std::map<std::string, std::vector<std::string>> by_topic;
        for (const auto& m : replies.messages) by_topic[m.topic].push_back(m.payload);
        REQUIRE(by_topic.size() == kMachines);
        for (int i = 0; i < kMachines; ++i) {
            const auto& got = by_topic["Query/Response/gw-" + std::to_string(i) + "/app"];
            REQUIRE(got.size() == 5);
            for (int round = 0; round < 5; ++round)
                CHECK(got[static_cast<std::size_t>(round)] == std::to_string(i) + ":" + std::to_string(round));
        }
    }
    // The broker may hand a reply to the application before the I/O thread
    // has read that publish's PUBACK on the machine's own socket: every
    // machine's window empties, but not necessarily before the last reply.
    CHECK(eventually(
        [&] { return std::all_of(machines.begin(), machines.end(), [](const auto& t) { return t->stats().in_flight == 0; }); },
        std::chrono::seconds(10)));
    for (const auto& t : machines) CHECK(t->stats().in_flight == 0);

    // A clean stop says goodbye: no last will.
    machines[0]->stop();
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    {
        std::lock_guard<std::mutex> lock(replies.mutex);
        for (const auto& m : replies.messages) CHECK(m.topic != "Notify/State/gw-0");
    }
    CHECK(machines[1]->state() == LinkState::connected);
    CHECK(threads_named("nclink-mqtt-io") >= 1);
    for (auto& t : machines) t->stop();
    app->stop();
}

namespace {
test::TestPki& tls_pki() {
    static test::TestPki made({"tls-user"});
    return made;
}
}  // namespace

TEST_CASE("over TLS: server verification with a password and mutual TLS connect but a bad password or a wrong CA never does") {
    GENERATE_CLIENT();
    if (auto missing = test::tls_tools_missing()) {
        WARN("TLS test skipped: " << *missing);
        return;
    }
    const bool mutual = GENERATE(false, true);
    INFO((mutual ? "mutual TLS" : "server verification and a password"));
    test::TlsListener listener;
    listener.require_certificate = mutual;
    MosquittoOptions bo;
    bo.password_file = tls_pki().password_file({{"tls-user", "pw-tls-user"}});
    bo.extra_config = test::tls_listener_config(tls_pki(), listener);
    MosquittoBroker broker(bo);

    auto tls_options = [&](const std::string& ca, const std::string& password) {
        MqttOptions o = options_for(broker, "nclink-test-tls");
        o.broker_url = "ssl://127.0.0.1:" + std::to_string(listener.port);
        o.username = "tls-user";
        if (!mutual) o.password = password;
        MqttTlsOptions t;
        t.ca_file = tls_pki().file(ca);
        if (mutual) {
            t.cert_file = tls_pki().file("tls-user.pem");
            t.key_file = tls_pki().file("tls-user.key");
        }
        o.tls = t;
        return o;
    };

    auto good = connect(tls_options("ca.pem", "pw-tls-user"));
    Inbox inbox;
    inbox.attach(*good);
    REQUIRE(good->subscribe({"tls/echo"}, 1).ok());
    REQUIRE(good->start().ok());
    REQUIRE(eventually([&] { return good->state() == LinkState::connected; }, std::chrono::seconds(10)));
    REQUIRE(eventually([&] {
        (void)good->publish({"tls/echo", "over TLS", 1, false});
        return eventually([&] { return inbox.count() > 0; }, std::chrono::milliseconds(300));
    }));
    CHECK(inbox.payloads().front() == "over TLS");
    good->stop();

    if (!mutual) {
        auto bad_password = connect(tls_options("ca.pem", "wrong"));
        REQUIRE(bad_password->start().ok());
        REQUIRE(eventually([&] { return bad_password->stats().connect_failures > 0; }, std::chrono::seconds(10)));
        CHECK(bad_password->state() != LinkState::connected);
        CHECK(bad_password->stats().refused);  // retrying will not help: programs exit on it at start
        CHECK(bad_password->stats().last_error.find("refused") != std::string::npos);
        bad_password->stop();
    }
    auto wrong_ca = connect(tls_options("other-ca.pem", "pw-tls-user"));
    REQUIRE(wrong_ca->start().ok());
    // Named without waiting for the connect timeout, and marked refused.
    REQUIRE(eventually([&] { return wrong_ca->stats().connect_failures > 0; }, std::chrono::seconds(3)));
    CHECK(eventually([&] { return wrong_ca->stats().refused; }, std::chrono::seconds(3)));
    CHECK(wrong_ca->stats().last_error.find("certificate did not verify") != std::string::npos);
    CHECK(wrong_ca->state() != LinkState::connected);
    CHECK(wrong_ca->stats().connects == 0);
    wrong_ca->stop();
}

// An MQTT 5 broker may end a connection with a DISCONNECT of its own (a
// session taken over, a server shutting down, a subscription it will not
// serve): paho reports that to a disconnected handler, not to the
// connection-lost one, and a transport listening only to the latter stayed
// "connected" and deaf. mosquitto sends DISCONNECT 0x8E (session taken over,
// MQTT 5.0 clause 3.14.2.1) when a second client connects with the same id.
TEST_CASE("a DISCONNECT from the broker is a lost connection: the transport connects again and hears its subscription") {
    GENERATE_CLIENT();
    MosquittoBroker broker;
    auto o = options_for(broker, "nclink-taken-over");
    o.mqtt_version = 5;
    auto taken = connect(o);
    Inbox inbox;
    inbox.attach(*taken);
    REQUIRE(taken->start().ok());
    REQUIRE(taken->subscribe({"taken/over"}, 1).ok());
    REQUIRE(eventually([&] { return taken->state() == LinkState::connected; }));

    // The same client id from elsewhere, connected and then gone.
    auto second = make_mqtt_transport(options_for(broker, "nclink-taken-over"), o_logger);
    REQUIRE(second.ok());
    REQUIRE((*second)->start().ok());
    REQUIRE(eventually([&] { return (*second)->state() == LinkState::connected; }));
    (*second)->stop(std::chrono::milliseconds(0));

    REQUIRE(eventually([&] { return taken->stats().connects >= 2 && taken->state() == LinkState::connected; }));
    auto publisher = connect(options_for(broker, "nclink-taken-over-publisher"));
    REQUIRE(publisher->start().ok());
    REQUIRE(eventually([&] {
        (void)publisher->publish({"taken/over", "heard", 1, false});
        return eventually([&] { return inbox.count() >= 1; }, std::chrono::milliseconds(300));
    }));
    publisher->stop();
    taken->stop();
}
