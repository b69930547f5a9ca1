// Delivery guarantees against a real mosquitto and the simulated mill
// (docs/delivery.md): the client's keep-alive keeps registrations past the
// adapter's application lease, the adapter releases only an application that
// is offline by GB/T 41970 3.22 and counts it, Sample and Event DTUs go at
// QoS 1 by default, and a persistent session gets what was published while
// the application was away.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include "support/collected.hpp"
#include "support/inbox.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/row_ledger.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <thread>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

const std::string kDev = kSimMillDevice;

AdapterConfig sim_config(const MosquittoBroker& broker) {
    AdapterConfig c;
    c.model_path = sim_mill_path();
    c.broker_url = broker.url();
    c.register_timeout = 500ms;
    c.events.poll_interval = 50ms;
    return c;
}

Client::EventRegistration moving_x() {
    Client::EventRegistration r;
    r.id = "x_position";
    r.filters = {Json{{"type", "change"}, {"variance", 0.5}}};
    return r;
}

std::unique_ptr<Client> app(const MosquittoBroker& broker, const std::string& ex, std::chrono::milliseconds keepalive) {
    return started_client(broker.url(), ex, 5s, [&](MqttOptions& m, ClientOptions& o) {
        m.client_id = "nclink-itest-" + ex;
        o.keepalive_interval = keepalive;
    });
}

std::uint64_t registered_events(const Adapter& adapter) {
    return adapter.stats().features["events"]["registered"].get<std::uint64_t>();
}

/// Ticks the sampler gave up after a very long stall (a loaded machine): holes
/// in the row times that are no loss on the way.
std::uint64_t skipped(const Adapter& adapter, const std::string& channel) {
    for (const auto& c : adapter.sampling_stats().channels)
        if (c.id == channel) return c.skipped_ticks;
    return 0;
}

}  // namespace

TEST_CASE("liveness: the client's keep-alive keeps its event and dynamic channel past the adapter's lease") {
    MosquittoBroker broker;
    auto config = sim_config(broker);
    config.application_lease = 1500ms;
    auto adapter = started_adapter(config, sim_for(sim_mill_path()));
    // Before the client: its thread may still deliver while it stops.
    Collected<EventData> events;
    Collected<SampleDtu> samples;
    auto client = app(broker, "keeper", 200ms);

    auto event = client->register_event(kDev, moving_x(), events.handler());
    REQUIRE(event.ok());
    auto channel = client->register_sampling(kDev, {"x_position"}, 10ms, 100ms, samples.handler());
    REQUIRE(channel.ok());

    // Three leases with no request from the application but the keep-alive.
    std::this_thread::sleep_for(4500ms);
    CHECK(adapter->stats().applications_released == 0);
    CHECK(registered_events(*adapter) == 1);
    CHECK(client->stats().keepalives >= 3);
    const auto events_then = events.size(), samples_then = samples.size();
    CHECK(eventually([&] { return events.size() > events_then && samples.size() > samples_then; }));
    REQUIRE(client->unregister_sampling(*channel).ok());
    REQUIRE(client->unregister_event(kDev, *event).ok());
}

TEST_CASE("liveness: without keep-alive the adapter releases after the lease and counts it") {
    MosquittoBroker broker;
    auto config = sim_config(broker);
    config.application_lease = 1000ms;
    auto adapter = started_adapter(config, sim_for(sim_mill_path()));
    // Before the client: its thread may still deliver while it stops.
    Collected<EventData> events;
    Collected<SampleDtu> samples;
    auto client = app(broker, "silent", 0ms);
    REQUIRE(client->register_event(kDev, moving_x(), events.handler()).ok());
    REQUIRE(client->register_sampling(kDev, {"x_position"}, 10ms, 100ms, samples.handler()).ok());
    REQUIRE(registered_events(*adapter) == 1);
    REQUIRE(eventually([&] { return adapter->stats().applications_released == 1; }));
    CHECK(registered_events(*adapter) == 0);
    CHECK(client->stats().keepalives == 0);
    const Json json = to_json(adapter->stats());
    CHECK(json["applications_released"] == 1);
    CHECK(json["features"]["sampling"]["dynamic"]["released"] == 1);
}

TEST_CASE("QoS: Sample and Event DTUs go at QoS 1 by default") {
    MosquittoBroker broker;
    auto adapter = started_adapter(sim_config(broker), sim_for(sim_mill_path()));
    MqttOptions m;
    m.broker_url = broker.url();
    m.client_id = "qos-peer";
    auto peer = make_mqtt_transport(m).value();
    Inbox inbox;
    inbox.attach(*peer);
    REQUIRE(peer->subscribe({"Sample/" + kDev + "/+", topics::event(kDev, "qos-app")}, 1).ok());
    REQUIRE(peer->start().ok());
    // Before the client: its thread may still deliver while it stops.
    Collected<EventData> events;
    auto client = app(broker, "qos-app", 60s);
    REQUIRE(client->register_event(kDev, moving_x(), events.handler()).ok());
    REQUIRE(eventually([&] {
        std::lock_guard<std::mutex> lock(inbox.mutex);
        bool sample = false, event = false;
        for (const auto& message : inbox.messages) {
            (message.topic.rfind("Sample/", 0) == 0 ? sample : event) = true;
        }
        return sample && event;
    }));
    std::lock_guard<std::mutex> lock(inbox.mutex);
    for (const auto& message : inbox.messages) {
        INFO(message.topic);
        CHECK(message.qos == 1);  // the broker delivers min(publish, subscription) QoS
    }
}

TEST_CASE("persistent session: the rows published while the application was away arrive when it is back") {
    MosquittoBroker broker;
    auto adapter = started_adapter(sim_config(broker), sim_for(sim_mill_path()));
    RowLedger ledger({{"ch_fast", 1}, {"ch_slow", 100}});
    const auto connect = [&](bool persistent) {
        MqttOptions m;
        m.broker_url = broker.url();
        m.client_id = persistent ? "nclink-itest-persistent" : "nclink-itest-clean";
        m.clean_session = !persistent;
        ClientOptions o;
        o.ex_cid = persistent ? "persistent" : "clean";
        auto client = Client::create(std::move(m), std::move(o)).value();
        // Before start: the broker hands over what it kept right after connecting.
        REQUIRE(client->subscribe_samples(kDev, [&](const SampleDtu& d) { ledger.add(d); }).ok());
        REQUIRE(client->start().ok());
        REQUIRE(client->wait_connected(10s));
        return client;
    };
    auto first = connect(true);
    REQUIRE(eventually([&] { return ledger.rows("ch_slow") >= 3; }));
    first->stop();
    first.reset();
    const auto rows_before = ledger.rows("ch_fast");
    std::this_thread::sleep_for(1500ms);  // about 15 ch_fast DTUs published meanwhile
    auto second = connect(true);
    REQUIRE(eventually([&] { return ledger.rows("ch_fast") >= rows_before + 2000; }));
    INFO("ch_fast rows " << ledger.rows("ch_fast") << ", holes " << ledger.holes());
    CHECK(ledger.holes() <= skipped(*adapter, "ch_fast") + skipped(*adapter, "ch_slow"));
    CHECK(ledger.duplicates() == 0);
}

TEST_CASE("clean session: the rows published while the application was away are gone") {
    // The contrast to the persistent session: the line of docs/delivery.md
    // that says clean_session=true keeps nothing.
    MosquittoBroker broker;
    auto adapter = started_adapter(sim_config(broker), sim_for(sim_mill_path()));
    RowLedger ledger({{"ch_fast", 1}});
    const auto connect = [&] {
        auto client = app(broker, "clean", 60s);
        REQUIRE(client->subscribe_samples(kDev, [&](const SampleDtu& d) { ledger.add(d); }).ok());
        return client;
    };
    auto first = connect();
    REQUIRE(eventually([&] { return ledger.rows("ch_fast") >= 300; }));
    first.reset();
    std::this_thread::sleep_for(1000ms);
    auto second = connect();
    const auto rows_back = ledger.rows("ch_fast");
    REQUIRE(eventually([&] { return ledger.rows("ch_fast") >= rows_back + 300; }));
    CHECK(ledger.holes() > skipped(*adapter, "ch_fast") + 100);  // about 1000 rows missed
}
