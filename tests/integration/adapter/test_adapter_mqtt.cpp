// End to end through a real mosquitto: the simulated mill behind an nclink
// Adapter, driven only through the wire by the client library and raw MQTT.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include "sim/sim_driver.hpp"
#include <nclink/topics.hpp>

#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <mutex>

using namespace nclink;
using nclink::test::eventually;
using nclink::test::MosquittoBroker;
using nclink::test::MosquittoOptions;
using nclink::test::ScratchDir;
using nclink::test::sim_for;
using nclink::test::sim_mill_path;
using nclink::test::started_adapter;
using nclink::test::started_client;

namespace {

const std::string kDev = nclink::test::kSimMillDevice;

// The simulator around a slot that can make reads slow (for the restart test).
class SlowableSim final : public Driver {
public:
    SlowableSim() : sim_(SimDriver::create(load_model_file(sim_mill_path()).model).value()) {}
    DriverInfo info() const override { return sim_->info(); }
    void read(const std::vector<PointRef>& p, std::vector<Result<Json>>& r) override {
        if (const auto d = delay.load(); d.count() > 0) std::this_thread::sleep_for(d);
        sim_->read(p, r);
    }
    Result<void> write(const WriteRequest& w) override { return sim_->write(w); }
    bool claims(std::string_view id) const override { return sim_->claims(id); }
    std::atomic<std::chrono::milliseconds> delay{std::chrono::milliseconds(0)};

private:
    std::unique_ptr<SimDriver> sim_;
};

struct Rig : nclink::test::SimMillRig {
    explicit Rig(MosquittoOptions broker_options = {}) : SimMillRig(broker_options) { driver = slowable; }

    void start_adapter(std::chrono::milliseconds driver_timeout = std::chrono::milliseconds(1000)) {
        config.driver_timeout = driver_timeout;
        start();
    }
    std::unique_ptr<Client> app(const std::string& ex, bool persistent = false) {
        return make_client(ex, std::chrono::seconds(5), [&](MqttOptions& m, ClientOptions&) { m.clean_session = !persistent; });
    }

    std::shared_ptr<SlowableSim> slowable = std::make_shared<SlowableSim>();
};

}  // namespace

TEST_CASE("probe, query and set the simulated mill through mosquitto") {
    Rig rig;
    rig.start_adapter();
    auto app = rig.app("mes-1");

    auto model = app->probe(kDev);
    REQUIRE(model.ok());
    CHECK(model.value()["devices"][0]["guid"] == kDev);

    auto q = app->query(kDev, {{"status", std::nullopt},
                               {"x_position", std::nullopt},
                               {"tools", Json{{"operation", "get_length"}}},
                               {"parameters", Json{{"operation", "get_keys"}}},
                               {"coordinates", Json{{"operation", "get_value"}, {"indexes", {"0"}}}},
                               {"manufacturer", std::nullopt},
                               {"no_such_item", std::nullopt}});
    REQUIRE(q.ok());
    const auto& r = q.value();
    REQUIRE(r.size() == 7);
    CHECK(r[0].status.ok);
    CHECK(r[0].values->at(0).is_string());
    CHECK(r[1].values->at(0).is_number());
    CHECK(r[2].values == Json::array({64}));
    CHECK(r[3].values->size() == 64);
    CHECK(r[4].values->at(0)["name"] == "G54");
    CHECK(r[5].values == Json::array({"nclink"}));
    CHECK_FALSE(r[6].status.ok);
    CHECK(r[6].status.error == 401);

    auto s = app->set(kDev, {SetItem{"feed_override", Json{{"value", 50}}, std::nullopt, std::nullopt},
                             SetItem{"status", Json{{"value", "free"}}, std::nullopt, std::nullopt},
                             SetItem{"tools", Json{{"index", 3}, {"value", Json{{"id", "T99"}}}}, std::nullopt, std::nullopt}});
    REQUIRE(s.ok());
    CHECK(s.value()[0].status.ok);
    CHECK(s.value()[1].status.error == 301);
    CHECK(s.value()[2].status.ok);
    auto after =
        app->query(kDev, {{"feed_override", std::nullopt}, {"tools", Json{{"operation", "get_value"}, {"indexes", {"3"}}}}});
    REQUIRE(after.ok());
    CHECK(after.value()[0].values == Json::array({50}));
    CHECK(after.value()[1].values->at(0)["id"] == "T99");
    rig.adapter->stop();
}

TEST_CASE("a response produced while the broker restarts is delivered after it") {
    MosquittoOptions bo;
    bo.persistent = true;  // the client's persistent session keeps its subscription
    Rig rig(bo);
    // The slow driver (below) slows the sampling and event reads too, and the
    // Query waits its turn behind them: a deadline well above those, so the
    // answer is the read's and not the watchdog's 203 on a loaded machine.
    rig.start_adapter(std::chrono::milliseconds(15000));
    auto app = rig.app("mes-restart", true);
    REQUIRE(app->query(kDev, {{"status", std::nullopt}}).ok());  // warm: subscriptions in place

    rig.slowable->delay = std::chrono::milliseconds(800);
    std::mutex mutex;
    std::optional<Result<std::vector<QueryResult>>> answer;
    RequestOptions ro;
    ro.timeout = std::chrono::seconds(40);
    app->query_async(
        kDev, {{"x_position", std::nullopt}},
        [&](Result<std::vector<QueryResult>> r) {
            std::lock_guard<std::mutex> lock(mutex);
            answer = std::move(r);
        },
        ro);
    // The adapter is inside the (slow) driver read when the broker goes away.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    rig.broker.stop();
    std::this_thread::sleep_for(std::chrono::milliseconds(900));  // the answer is ready and buffered now
    rig.broker.start();
    REQUIRE(eventually(
        [&] {
            std::lock_guard<std::mutex> lock(mutex);
            return answer.has_value();
        },
        std::chrono::seconds(45)));
    std::lock_guard<std::mutex> lock(mutex);
    REQUIRE(answer->ok());
    const auto& status = answer->value()[0].status;
    INFO("item status: " << status.error.value_or(0) << " " << status.reason.value_or(""));
    CHECK(status.ok);
    rig.slowable->delay = std::chrono::milliseconds(0);
    rig.adapter->stop();
}

TEST_CASE("adapter restart: applications see offline, then online again") {
    Rig rig;
    rig.start_adapter();
    // Declared before the client: its dispatch thread may call the handler
    // until the client is destroyed, so these must outlive it.
    std::mutex mutex;
    std::vector<std::string> states;
    auto app = rig.app("mes-state");
    REQUIRE(app->subscribe_state(kDev,
                                 [&](const NotifyState& n) {
                                     std::lock_guard<std::mutex> lock(mutex);
                                     states.push_back(n.state);
                                 })
                .ok());
    auto seen = [&](std::size_t n) {
        return eventually([&] {
            std::lock_guard<std::mutex> lock(mutex);
            return states.size() >= n;
        });
    };
    REQUIRE(seen(1));
    rig.adapter->stop();
    REQUIRE(seen(2));
    rig.adapter.reset();
    rig.start_adapter();
    REQUIRE(seen(3));
    {
        std::lock_guard<std::mutex> lock(mutex);
        CHECK(states == std::vector<std::string>{"online", "offline", "online"});
    }
    rig.adapter->stop();
}

TEST_CASE("raw MQTT: malformed and retained requests through the real broker") {
    Rig rig;
    MqttOptions m;
    m.broker_url = rig.broker.url();
    m.client_id = "nclink-itest-raw";
    auto raw = make_mqtt_transport(m).value();
    std::mutex mutex;
    std::vector<Message> inbox;
    raw->set_message_handler([&](const Message& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        inbox.push_back(msg);
    });
    REQUIRE(raw->start().ok());
    REQUIRE(raw->subscribe({"Query/Response/" + kDev + "/raw", "Set/Response/" + kDev + "/raw"}, 1).ok());
    REQUIRE(eventually([&] { return raw->state() == LinkState::connected; }));
    // Published retained before the adapter exists: replayed to it on subscribe, ignored.
    REQUIRE(raw->publish({"Set/Request/" + kDev + "/raw",
                          R"({"@id":"stale","values":[{"id":"feed_override","params":{"value":5}}]})", 1, true})
                .ok());
    REQUIRE(raw->flush(std::chrono::seconds(5)));
    rig.start_adapter();
    REQUIRE(raw->publish({"Query/Request/" + kDev + "/raw", "{not json", 1, false}).ok());
    REQUIRE(raw->publish({"Query/Request/" + kDev + "/raw", R"({"@id":"ok","ids":[{"id":"feed_override"}]})", 1, false}).ok());
    REQUIRE(eventually([&] {
        std::lock_guard<std::mutex> lock(mutex);
        return inbox.size() >= 2;
    }));
    std::lock_guard<std::mutex> lock(mutex);
    // Two request workers: the answers may arrive in either order.
    Json malformed, ok;
    for (const auto& msg : inbox) {
        const Json body = Json::parse(msg.payload);
        (body.contains("@id") ? ok : malformed) = body;
    }
    CHECK(malformed.value("error", 0) == 412);
    REQUIRE(ok.value("@id", "") == "ok");
    REQUIRE(ok["values"].size() == 1);
    CHECK(ok["values"][0]["values"][0] != 5);  // the stale retained Set was not applied
    for (const auto& msg : inbox) CHECK(msg.topic != "Set/Response/" + kDev + "/raw");
    CHECK(rig.adapter->stats().ignored_retained == 1);
    raw->stop();
    rig.adapter->stop();
}
