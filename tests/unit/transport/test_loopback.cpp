// Transport semantics (ordering, offline buffer, wills, retained) exercised
// through the in-process loopback, which shares the outbox with MQTT.
#include <nclink/testing/loopback_transport.hpp>

#include "support/inbox.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <mutex>
#include <string>
#include <vector>

using namespace nclink;
using nclink::test::eventually;
using nclink::test::Inbox;

namespace {

std::unique_ptr<Transport> client(LoopbackBroker& broker, const std::string& id, OutboxLimits limits = {}) {
    LoopbackOptions o;
    o.client_id = id;
    o.outbox = limits;
    return make_loopback_transport(broker, o);
}

}  // namespace

TEST_CASE("messages reach matching subscribers in publish order") {
    LoopbackBroker broker;
    auto pub = client(broker, "pub");
    auto sub = client(broker, "sub");
    Inbox inbox;
    inbox.attach(*sub);
    REQUIRE(pub->start().ok());
    REQUIRE(sub->start().ok());
    REQUIRE(eventually([&] { return sub->state() == LinkState::connected && pub->state() == LinkState::connected; }));
    REQUIRE(sub->subscribe({"Sample/dev/+"}, 0).ok());
    for (int i = 0; i < 500; ++i) REQUIRE(pub->publish({"Sample/dev/ch", std::to_string(i), 0, false}).ok());
    REQUIRE(pub->publish({"Other/topic", "x", 0, false}).ok());
    REQUIRE(eventually([&] { return inbox.count() == 500; }));
    const auto got = inbox.payloads();
    for (int i = 0; i < 500; ++i) REQUIRE(got[static_cast<std::size_t>(i)] == std::to_string(i));
    CHECK(pub->stats().published == 501);
    CHECK(sub->stats().received == 500);
}

TEST_CASE("while the broker is away messages wait and go out in order afterwards") {
    LoopbackBroker broker;
    auto pub = client(broker, "pub");
    auto sub = client(broker, "a-sub");  // reconnects (and resubscribes) before "pub"
    Inbox inbox;
    inbox.attach(*sub);
    REQUIRE(pub->start().ok());
    REQUIRE(sub->start().ok());
    REQUIRE(eventually([&] { return pub->state() == LinkState::connected; }));
    REQUIRE(sub->subscribe({"t/#"}, 1).ok());
    REQUIRE(pub->publish({"t/a", "before", 1, false}).ok());
    REQUIRE(eventually([&] { return inbox.count() == 1; }));

    broker.set_online(false);
    REQUIRE(eventually([&] { return pub->state() == LinkState::disconnected; }));
    for (int i = 0; i < 20; ++i) REQUIRE(pub->publish({"t/a", "offline-" + std::to_string(i), 1, false}).ok());
    CHECK(pub->stats().buffered == 20);

    broker.set_online(true);  // the subscriber resubscribes on reconnect
    REQUIRE(eventually([&] { return inbox.count() == 21; }));
    const auto got = inbox.payloads();
    for (int i = 0; i < 20; ++i) CHECK(got[static_cast<std::size_t>(i) + 1] == "offline-" + std::to_string(i));
    CHECK(pub->stats().buffered == 0);
    CHECK(pub->stats().dropped == 0);
}

TEST_CASE("a full offline buffer drops the oldest messages and counts them") {
    LoopbackBroker broker;
    broker.set_online(false);
    OutboxLimits limits;
    limits.max_bytes = 100;  // topic "t" + 9-byte payloads = 10 bytes each
    auto pub = client(broker, "pub", limits);
    // Sessions reconnect in id order: "a-sub" is back (and subscribed) before
    // "pub" starts sending, so it sees everything that was kept.
    auto sub = client(broker, "a-sub");
    Inbox inbox;
    inbox.attach(*sub);
    REQUIRE(pub->start().ok());
    REQUIRE(sub->start().ok());
    REQUIRE(sub->subscribe({"t"}, 1).ok());  // remembered while offline
    for (int i = 0; i < 15; ++i) REQUIRE(pub->publish({"t", fmt::format("msg-{:05}", i), 1, false}).ok());
    const auto stats = pub->stats();
    CHECK(stats.dropped == 5);
    CHECK(stats.dropped_bytes == 50);
    CHECK(stats.buffered == 10);
    CHECK(stats.buffered_bytes == 100);

    // A message larger than the whole buffer is refused, not silently lost.
    auto too_big = pub->publish({"t", std::string(200, 'x'), 1, false});
    REQUIRE_FALSE(too_big.ok());
    CHECK(too_big.error().code == ErrorCode::memory_configured);

    broker.set_online(true);
    REQUIRE(eventually([&] { return inbox.count() == 10; }));
    const auto got = inbox.payloads();
    for (int i = 0; i < 10; ++i) CHECK(got[static_cast<std::size_t>(i)] == fmt::format("msg-{:05}", i + 5));
    CHECK(pub->stats().buffered == 0);
}

TEST_CASE("retained messages reach late subscribers with the retained flag") {
    LoopbackBroker broker;
    auto pub = client(broker, "pub");
    REQUIRE(pub->start().ok());
    REQUIRE(eventually([&] { return pub->state() == LinkState::connected; }));
    REQUIRE(pub->publish({"Notify/State/dev", R"({"state":"online"})", 1, true}).ok());
    REQUIRE(pub->flush(std::chrono::seconds(5)));
    REQUIRE(broker.retained("Notify/State/dev").has_value());

    auto sub = client(broker, "sub");
    Inbox inbox;
    inbox.attach(*sub);
    REQUIRE(sub->start().ok());
    REQUIRE(eventually([&] { return sub->state() == LinkState::connected; }));
    REQUIRE(sub->subscribe({"Notify/State/+"}, 1).ok());
    REQUIRE(eventually([&] { return inbox.count() == 1; }));
    std::lock_guard<std::mutex> lock(inbox.mutex);
    CHECK(inbox.messages[0].retained);
    CHECK(inbox.messages[0].payload == R"({"state":"online"})");
}

TEST_CASE("a dropped client's last will is published, a clean stop publishes none") {
    LoopbackBroker broker;
    LoopbackOptions o;
    o.client_id = "adapter";
    o.last_will = Message{"Notify/State/dev", R"({"state":"offline"})", 1, true};
    auto adapter = make_loopback_transport(broker, o);
    auto app = client(broker, "app");
    Inbox inbox;
    inbox.attach(*app);
    REQUIRE(adapter->start().ok());
    REQUIRE(app->start().ok());
    REQUIRE(eventually([&] { return app->state() == LinkState::connected; }));
    REQUIRE(app->subscribe({"Notify/State/dev"}, 1).ok());

    REQUIRE(broker.drop_client("adapter"));
    REQUIRE(eventually([&] { return inbox.count() == 1; }));
    REQUIRE(eventually([&] { return adapter->state() == LinkState::connected; }));  // reconnected

    adapter->stop();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(inbox.count() == 1);
}

TEST_CASE("handlers may publish: a request/response echo") {
    LoopbackBroker broker;
    auto server = client(broker, "server");
    auto app = client(broker, "app");
    Transport* server_ptr = server.get();
    server->set_message_handler([server_ptr](const Message& m) {
        (void)server_ptr->publish({"Echo/Response", m.payload, 1, false});
    });
    Inbox inbox;
    inbox.attach(*app);
    REQUIRE(server->start().ok());
    REQUIRE(app->start().ok());
    REQUIRE(eventually([&] { return server->state() == LinkState::connected && app->state() == LinkState::connected; }));
    REQUIRE(server->subscribe({"Echo/Request"}, 1).ok());
    REQUIRE(app->subscribe({"Echo/Response"}, 1).ok());
    for (int i = 0; i < 50; ++i) REQUIRE(app->publish({"Echo/Request", std::to_string(i), 1, false}).ok());
    REQUIRE(eventually([&] { return inbox.count() == 50; }));
    CHECK(inbox.payloads().back() == "49");
}

TEST_CASE("publishing after stop is refused") {
    LoopbackBroker broker;
    auto t = client(broker, "x");
    REQUIRE(t->start().ok());
    t->stop();
    auto r = t->publish({"t", "p", 0, false});
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::unavailable);
}
