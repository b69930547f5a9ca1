// GB/T 41970-2022 8.3, connection error scenarios 2 and 5, end to end over a
// real mosquitto, and the client's model cache and standing registrations
// (8.2.5.3, 8.2.7.3, 8.3.6) across a model change and an adapter restart.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <mutex>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::MosquittoBroker;
using nclink::test::MosquittoOptions;
using nclink::test::ScratchDir;
using nclink::test::started_client;

namespace {

const std::string kDev = "test-dev";
std::string model_path() { return std::string(NCLINK_TEST_DATA_DIR) + "/adapter-test-model.json"; }

/// Values in a map; reads wait `delay` (to hold a response back).
class MapDriver final : public Driver {
public:
    DriverInfo info() const override { return {"map", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        if (const auto d = delay.load(); d.count() > 0) std::this_thread::sleep_for(d);
        std::lock_guard<std::mutex> lock(mutex);
        for (std::size_t i = 0; i < points.size(); ++i) {
            auto it = values.find(points[i].id);
            results[i] =
                it == values.end() ? Result<Json>(make_error(ErrorCode::unavailable, "no value")) : Result<Json>(it->second);
        }
    }
    Result<void> write(const WriteRequest& request) override {
        std::lock_guard<std::mutex> lock(mutex);
        values[request.id] = request.new_value;
        return ok_result();
    }
    void put(const std::string& id, Json v) {
        std::lock_guard<std::mutex> lock(mutex);
        values[id] = std::move(v);
    }
    std::mutex mutex;
    std::map<std::string, Json> values{{"pos", 1.5}, {"status", "running"}, {"ovr", 100}};
    std::atomic<std::chrono::milliseconds> delay{0ms};
};

struct Rig {
    explicit Rig(MosquittoOptions options = {}) : broker(options) {}

    std::unique_ptr<Adapter> start_adapter() {
        AdapterConfig config;
        config.model_path = model_path();
        std::filesystem::create_directories(dir.path);
        config.persistence_dir = dir.path.string();
        config.broker_url = broker.url();
        config.register_timeout = 500ms;
        config.events.poll_interval = 20ms;
        auto adapter = std::make_unique<Adapter>(config, driver);
        REQUIRE(adapter->start().ok());
        REQUIRE(eventually([&] { return adapter->state() == AdapterState::normal; }, 20s));
        return adapter;
    }
    /// A raw MQTT terminal (no client library), to see exactly what arrives.
    std::unique_ptr<Transport> raw(const std::string& id, bool clean_session, std::vector<Message>& inbox, std::mutex& mutex) {
        MqttOptions o;
        o.broker_url = broker.url();
        o.client_id = id;
        o.clean_session = clean_session;
        auto t = make_mqtt_transport(o).value();
        t->set_message_handler([&](const Message& m) {
            std::lock_guard<std::mutex> lock(mutex);
            inbox.push_back(m);
        });
        return t;
    }

    MosquittoBroker broker;
    ScratchDir dir{"nclink-scenarios-"};
    std::shared_ptr<MapDriver> driver = std::make_shared<MapDriver>();
};

std::size_t count_on(std::vector<Message>& inbox, std::mutex& mutex, const std::string& topic, const std::string& needle = "") {
    std::lock_guard<std::mutex> lock(mutex);
    std::size_t n = 0;
    for (const auto& m : inbox) n += m.topic == topic && m.payload.find(needle) != std::string::npos;
    return n;
}

/// A standing event registration on "ovr" and what it delivered: `arrives`
/// puts a value into the machine and waits for its event.
struct OvrEvents {
    std::atomic<int> events{0};
    std::mutex mutex;
    Json last;
    std::string id;  ///< the id the application was given

    void register_on(Client& client, MapDriver& driver) {
        Client::EventRegistration registration;
        registration.id = "ovr";
        auto made = client.register_event(kDev, registration, [this](const EventData& e) {
            std::lock_guard<std::mutex> lock(mutex);
            last = e.event.value;
            ++events;
        });
        REQUIRE(made.ok());
        id = made.value();
        REQUIRE(arrives(driver, 110));
    }
    bool arrives(MapDriver& driver, int value) {
        const int before = events;
        driver.put("ovr", value);
        return eventually(
            [&] {
                std::lock_guard<std::mutex> lock(mutex);
                return events > before && last == Json(value);
            },
            20s);
    }
};

}  // namespace

TEST_CASE("8.3.3 scenario 2: the application's link fails after its request, the adapter answers, the response waits for it") {
    Rig rig;
    auto adapter = rig.start_adapter();
    std::mutex mutex;
    std::vector<Message> inbox;
    const std::string reply = topics::query_response(kDev, "mes");
    {
        auto app = rig.raw("mes", false, inbox, mutex);  // a persistent session: the broker keeps its QoS 1 messages
        REQUIRE(app->start().ok());
        REQUIRE(eventually([&] { return app->state() == LinkState::connected; }, 20s));
        REQUIRE(app->subscribe({reply}, 1).ok());
        std::this_thread::sleep_for(300ms);  // the SUBACK
        rig.driver->delay = 600ms;           // the response x comes after the application is gone (within driver_timeout)
        REQUIRE(app->publish(Message{topics::query_request(kDev, "mes"),
                                     Json{{"@id", "x"}, {"guid", kDev}, {"ids", Json::array({Json{{"id", "pos"}}})}}.dump(), 1,
                                     false})
                    .ok());
        REQUIRE(app->flush(5s));
        app->stop(0ms);  // Time-1: the application's link fails
    }
    // The adapter's link is fine: it handles x and hands the response over
    // (c of 8.3.3), staying normal; nothing is kept on its side.
    REQUIRE(eventually([&] { return adapter->stats().requests >= 1; }, 20s));
    std::this_thread::sleep_for(1500ms);  // x has been answered by now
    rig.driver->delay = 0ms;
    CHECK(adapter->state() == AdapterState::normal);
    CHECK(count_on(inbox, mutex, reply) == 0);

    // The application's link is back: the response x kept for it arrives,
    // and a new request y is answered as usual.
    auto app = rig.raw("mes", false, inbox, mutex);
    REQUIRE(app->start().ok());
    REQUIRE(eventually([&] { return count_on(inbox, mutex, reply, "\"x\"") == 1; }, 20s));
    REQUIRE(app->subscribe({reply}, 1).ok());
    std::this_thread::sleep_for(300ms);
    REQUIRE(app->publish(Message{topics::query_request(kDev, "mes"),
                                 Json{{"@id", "y"}, {"guid", kDev}, {"ids", Json::array({Json{{"id", "pos"}}})}}.dump(), 1, false})
                .ok());
    REQUIRE(eventually([&] { return count_on(inbox, mutex, reply, "\"y\"") == 1; }, 20s));
    app->stop(0ms);
}

TEST_CASE(
    "8.3.6 scenario 5: both links fail (the broker stops), afterwards the adapter registers again and queued requests are "
    "answered") {
    MosquittoOptions persistent;
    persistent.persistent = true;
    Rig rig(persistent);
    auto adapter = rig.start_adapter();
    std::mutex mutex;
    std::vector<Message> inbox;
    auto monitor = rig.raw("monitor", false, inbox, mutex);
    REQUIRE(monitor->start().ok());
    REQUIRE(eventually([&] { return monitor->state() == LinkState::connected; }, 20s));
    REQUIRE(monitor->subscribe({topics::register_request(), topics::probe_version(kDev)}, 1).ok());
    std::this_thread::sleep_for(300ms);
    auto client = started_client(rig.broker.url(), "mes", 30s);
    REQUIRE(client->query(kDev, {QueryItem{"pos", std::nullopt}}).ok());
    const auto registrations = count_on(inbox, mutex, topics::register_request());

    rig.broker.stop();  // Time-1: neither link works
    REQUIRE(eventually([&] { return adapter->state() == AdapterState::disconnected; }, 20s));
    REQUIRE(eventually([&] { return client->state() == ClientState::disconnected; }, 20s));
    // The application keeps its request (b of 8.3.6: cache and send again).
    std::promise<Result<std::vector<QueryResult>>> answered;
    client->query_async(kDev, {QueryItem{"status", std::nullopt}},
                        [&](Result<std::vector<QueryResult>> r) { answered.set_value(std::move(r)); });
    CHECK(client->stats().queued == 1);

    rig.broker.start();
    // The links come back: the adapter registers again (8.3.6, last
    // paragraph) and announces its version; the queued request is answered,
    // sent again on that announcement if it went out before the adapter had
    // subscribed (ClientStats::resent).
    REQUIRE(eventually([&] { return adapter->state() == AdapterState::normal; }, 30s));
    REQUIRE(eventually([&] { return count_on(inbox, mutex, topics::register_request()) > registrations; }, 30s));
    auto future = answered.get_future();
    REQUIRE(future.wait_for(30s) == std::future_status::ready);
    auto result = future.get();
    INFO((result.ok() ? std::string("ok") : result.error().describe()));
    REQUIRE(result.ok());
    REQUIRE(result.value().size() == 1);
    CHECK(result.value()[0].status.ok);
    CHECK(result.value()[0].values == Json::array({"running"}));
    monitor->stop(0ms);
}

TEST_CASE("client model cache: after a broker restart the same adapter run keeps its registrations, none is made again") {
    MosquittoOptions persistent;
    persistent.persistent = true;
    persistent.save_every_change = true;
    Rig rig(persistent);
    auto adapter = rig.start_adapter();
    MqttOptions m;
    m.broker_url = rig.broker.url();
    m.client_id = "mes-persistent";
    m.clean_session = false;
    m.reconnect_max = 500ms;
    ClientOptions o;
    o.ex_cid = "mes";
    o.default_timeout = 10s;
    auto client = Client::create(m, o).value();
    REQUIRE(client->start().ok());
    REQUIRE(client->wait_connected(10s));
    OvrEvents ovr;
    ovr.register_on(*client, *rig.driver);

    // The broker stops (a clean stop publishes the adapter's last will:
    // Notify/State offline) and comes back; the adapter announces its version
    // again, naming the same run.
    rig.broker.stop();
    REQUIRE(eventually([&] { return adapter->state() == AdapterState::disconnected; }, 20s));
    rig.broker.start();
    REQUIRE(eventually([&] { return adapter->state() == AdapterState::normal; }, 30s));
    REQUIRE(eventually([&] { return client->state() == ClientState::normal; }, 30s));
    std::this_thread::sleep_for(1s);  // time for a Probe/Version and a (wrong) re-registration
    CHECK(client->reregistrations() == 0);
    REQUIRE(ovr.arrives(*rig.driver, 120));
    CHECK(client->stats().unmatched_responses == 0);
    CHECK(client->unregister_event(kDev, ovr.id).ok());  // the first id is still the adapter's
    client->stop();
}

TEST_CASE("client model cache: re-probes on a new version and registers again after an adapter restart") {
    Rig rig;
    auto adapter = rig.start_adapter();
    auto client = started_client(rig.broker.url(), "mes", 10s);
    std::atomic<int> models{0};
    REQUIRE(client->follow_model(kDev, [&](const std::string&, const Json&) { ++models; }).ok());
    REQUIRE(eventually([&] { return client->cached_model_version(kDev) == "1.0.0"; }, 20s));

    // A model change at run time: Probe/Version announces it, the cache fetches it.
    Json model = Json::parse(std::ifstream(model_path()));
    model["devices"][0]["version"] = "1.1.0";
    model["devices"][0]["dataItems"].push_back(Json{{"id", "temp"}, {"type", "TEMPERATURE"}});
    REQUIRE(adapter->replace_model(model.dump()).ok());
    REQUIRE(eventually([&] { return client->cached_model_version(kDev) == "1.1.0"; }, 20s));
    CHECK(client->cached_model(kDev)->dump().find("\"temp\"") != std::string::npos);
    CHECK(eventually([&] { return models >= 2; }, 10s));  // the callback runs just after the cache is updated

    // A standing event registration survives an adapter restart.
    OvrEvents ovr;
    ovr.register_on(*client, *rig.driver);

    adapter->stop();
    adapter.reset();
    adapter = rig.start_adapter();  // a new run: it knows no registration
    REQUIRE(eventually([&] { return client->reregistrations() >= 1; }, 30s));
    REQUIRE(ovr.arrives(*rig.driver, 120));
    // The id the application holds still unregisters it.
    CHECK(client->unregister_event(kDev, ovr.id).ok());
}
