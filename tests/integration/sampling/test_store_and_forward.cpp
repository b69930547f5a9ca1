// Offline store-and-forward through a real mosquitto: the broker is stopped
// and restarted while a channel streams, and every row is checked.
//
// Determinism: the driver's value IS the row number (a counter bumped by each
// read of the item), so the rows received must be exactly 0, 1, 2, ... with
// no gap and no repeat, whatever the wall clock did. The channel is a dynamic
// one at QoS 1 (privateInfo {"qos": 1}); the broker runs with persistence and
// the application subscribes with a persistent session, so what the broker
// had accepted survives its restart (the broker's durability is not under
// test: the adapter's is). The broker is stopped with SIGTERM.
#include <nclink/adapter.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <random>
#include <set>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::MosquittoBroker;
using nclink::test::MosquittoOptions;
using nclink::test::ScratchDir;
using nclink::test::sim_for;
using nclink::test::started_adapter;
using nclink::test::started_client;
namespace fs = std::filesystem;

namespace {

constexpr const char* kDev = "test-dev";

/// "ovr" reads 0, 1, 2, ...; everything else reads a constant.
class CounterDriver final : public Driver {
public:
    DriverInfo info() const override { return {"counter", "1", false}; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = points[i].id == "ovr" ? Json(next.fetch_add(1)) : Json(1.5);
    }
    Result<void> write(const WriteRequest&) override { return ok_result(); }
    std::atomic<std::int64_t> next{0};
};

MosquittoOptions persistent_broker() {
    MosquittoOptions o;
    o.persistent = true;
    return o;
}

struct Rig {
    MosquittoBroker broker{persistent_broker()};
    ScratchDir scratch{"nclink-itest-spool-"};
    fs::path dir = scratch.path;
    std::shared_ptr<CounterDriver> driver = std::make_shared<CounterDriver>();
    std::unique_ptr<Adapter> adapter;
    std::unique_ptr<Transport> app;
    std::mutex mutex;
    std::vector<Message> inbox;
    std::string channel;

    explicit Rig(std::size_t spool_bytes) {
        AdapterConfig config;
        config.broker_url = broker.url();
        config.model_path = std::string(NCLINK_TEST_DATA_DIR) + "/adapter-test-model.json";
        config.persistence_dir = (dir / "state").string();
        config.register_timeout = 200ms;
        config.sampling.spool_memory_bytes = spool_bytes;
        adapter = std::make_unique<Adapter>(config, driver);
        REQUIRE(adapter->start().ok());

        MqttOptions o;
        o.broker_url = broker.url();
        o.client_id = "app";
        o.clean_session = false;  // queued QoS 1 messages wait for us across the restart
        o.reconnect_min = 50ms;
        o.reconnect_max = 200ms;
        app = make_mqtt_transport(o).value();
        app->set_message_handler([this](const Message& m) {
            std::lock_guard<std::mutex> lock(mutex);
            inbox.push_back(m);
        });
        REQUIRE(app->subscribe({topics::dynamic_sample(kDev, "app", "+"), topics::sample_register_response(kDev, "app"),
                                topics::sample_unregister_response(kDev, "app")},
                               1)
                    .ok());
        REQUIRE(app->start().ok());
        REQUIRE(eventually([&] { return app->state() == LinkState::connected; }));
        REQUIRE(eventually([&] { return adapter->state() == AdapterState::normal; }));
        // The SUBACK is asynchronous: register until an answer comes back.
        REQUIRE(eventually([&] {
            send(topics::sample_register_request(kDev, "app"),
                 Json{{"@id", "reg"},
                      {"guid", kDev},
                      {"sampleInterval", 4},
                      {"uploadInterval", 20},
                      {"ids", Json::array({Json{{"id", "ovr"}}, Json{{"id", "pos"}}})},
                      {"privateInfo", {{"qos", 1}}}});
            return eventually([&] { return !on(topics::sample_register_response(kDev, "app")).empty(); }, 500ms);
        }));
        const Json reply = Json::parse(on(topics::sample_register_response(kDev, "app")).front().payload);
        REQUIRE(reply["code"] == "OK");
        channel = reply["id"].get<std::string>();
    }
    ~Rig() {
        if (adapter) adapter->stop(0ms);
        if (app) app->stop(0ms);
    }

    void send(const std::string& topic, const Json& payload) {
        REQUIRE(app->publish(Message{topic, payload.dump(), 1, false}).ok());
    }
    std::vector<Message> on(const std::string& topic) {
        std::lock_guard<std::mutex> lock(mutex);
        std::vector<Message> out;
        for (const auto& m : inbox)
            if (m.topic == topic) out.push_back(m);
        return out;
    }
    /// Each DTU once, in arrival order. QoS 1 is at-least-once: the broker
    /// sends again, after its restart, what it had sent but not seen
    /// acknowledged when it stopped; the client library drops such repeats
    /// by beginTime (docs/delivery.md), and so does this raw subscriber.
    std::vector<Json> dtus() {
        std::vector<Json> out;
        std::set<std::string> seen;
        for (const auto& m : on(topics::dynamic_sample(kDev, "app", channel))) {
            Json dtu = Json::parse(m.payload);
            if (seen.insert(dtu["beginTime"].dump()).second) out.push_back(std::move(dtu));
        }
        return out;
    }
    std::size_t rows() {
        std::size_t n = 0;
        for (const auto& d : dtus()) n += d["data"][0]["data"].size();
        return n;
    }
    Json spool() { return adapter->stats().features.at("sampling").at("spool"); }

    /// Stops the channel (Unregister/Sample) and waits until its last rows are in.
    void finish() {
        send(topics::sample_unregister_request(kDev, "app"), Json{{"@id", "unreg"}, {"guid", kDev}, {"id", channel}});
        REQUIRE(eventually([&] { return !on(topics::sample_unregister_response(kDev, "app")).empty(); }));
        // Every read the driver answered must arrive: wait for the last value.
        REQUIRE(eventually(
            [&] {
                const auto all = dtus();
                if (all.empty()) return false;
                Json last;
                for (const auto& value : all.back()["data"][0]["data"])
                    if (!value.is_null()) last = value;
                return last == driver->next.load() - 1 && spool()["pending"] == 0;
            },
            20s));
    }
};

bool is_replayed(const Json& dtu) {
    return dtu.contains("privateInfo") && dtu["privateInfo"].is_object() && dtu["privateInfo"].value("replayed", false);
}

}  // namespace

TEST_CASE("broker stopped and restarted mid-stream: every row arrives once and in order and replayed rows are marked") {
    Rig rig(4u << 20);
    REQUIRE(eventually([&] { return rig.rows() >= 100; }));
    rig.broker.stop();  // mid-stream: the channel keeps sampling every 4 ms
    REQUIRE(eventually([&] { return rig.spool()["spooled"].get<int>() >= 25; }, 20s));
    rig.broker.start();
    REQUIRE(eventually([&] { return rig.spool()["replayed"].get<int>() >= 25 && rig.spool()["pending"] == 0; }, 30s));
    const std::size_t after_replay = rig.rows();
    REQUIRE(eventually([&] { return rig.rows() >= after_replay + 50; }, 20s));  // live again
    rig.finish();

    // Row by row: the values are 0, 1, 2, ... A null is a tick whose read
    // never happened (a late tick on a loaded machine, sampling.md): it
    // consumed no number, so it cannot hide a lost row.
    std::int64_t expected = 0;
    std::size_t marked = 0, unmarked_after_marked = 0;
    bool seen_marked = false;
    for (const auto& dtu : rig.dtus()) {
        const bool replayed = is_replayed(dtu);
        marked += replayed ? 1 : 0;
        if (seen_marked && !replayed) ++unmarked_after_marked;
        seen_marked = seen_marked || replayed;
        for (const auto& value : dtu["data"][0]["data"]) {
            if (value.is_null()) continue;
            INFO("beginTime " << dtu["beginTime"] << (replayed ? " (replayed)" : ""));
            REQUIRE(value == expected);
            ++expected;
        }
        CHECK(dtu["data"][1]["data"].size() == dtu["data"][0]["data"].size());  // columns stay aligned
    }
    CHECK(expected == rig.driver->next.load());  // the last read arrived too: nothing lost at the tail
    const Json spool = rig.spool();
    CHECK(spool["dropped"] == 0);
    // (The spool also replayed the model channel ch1, which we do not subscribe to.)
    CHECK(marked <= spool["replayed"].get<std::size_t>());
    CHECK(marked >= 10);
    CHECK(unmarked_after_marked > 0);  // live data after the replay carries no marker
}

TEST_CASE("broker outage longer than the spool budget: the oldest DTUs are dropped and counted and the rest arrive in order") {
    Rig rig(1200);  // a handful of ~170-byte DTUs
    REQUIRE(eventually([&] { return rig.rows() >= 50; }));
    rig.broker.stop();
    REQUIRE(eventually([&] { return rig.spool()["dropped"].get<int>() >= 20; }, 20s));
    rig.broker.start();
    REQUIRE(eventually([&] { return rig.spool()["replayed"].get<int>() > 0 && rig.spool()["pending"] == 0; }, 30s));
    const std::size_t after_replay = rig.rows();
    REQUIRE(eventually([&] { return rig.rows() >= after_replay + 50; }, 20s));
    rig.finish();

    // Rows are contiguous except for exactly one gap: the dropped DTUs, right
    // before the first replayed one.
    std::int64_t expected = 0;
    int gaps = 0;
    bool gap_before_first_marked = false, seen_marked = false;
    for (const auto& dtu : rig.dtus()) {
        const auto& values = dtu["data"][0]["data"];
        std::int64_t first = -1;
        for (const auto& value : values)
            if (!value.is_null()) {
                first = value.get<std::int64_t>();
                break;
            }
        if (first < 0) continue;     // only late ticks in this DTU
        REQUIRE(first >= expected);  // never a repeat or a step back
        if (first > expected) {
            ++gaps;
            if (is_replayed(dtu) && !seen_marked) gap_before_first_marked = true;
        }
        seen_marked = seen_marked || is_replayed(dtu);
        expected = first;
        for (const auto& value : values) {
            if (value.is_null()) continue;
            REQUIRE(value == expected);
            ++expected;
        }
    }
    CHECK(expected == rig.driver->next.load());
    CHECK(gaps == 1);
    CHECK(gap_before_first_marked);
    const Json spool = rig.spool();
    CHECK(spool["dropped"].get<int>() >= 20);
    CHECK(spool["spooled"].get<int>() == spool["replayed"].get<int>() + spool["dropped"].get<int>());
}
