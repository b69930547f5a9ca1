// An adapter with a fake driver (support/fake_driver.hpp), and an
// application-side transport to talk to it through the wire (DTUs on topics).
// On the in-process loopback by default; with NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
// defined, through a real mosquitto on a free loopback port (MQTT transports
// on both sides), so the same tests run as integration tests (the
// CMakeLists.txt of tests/integration/adapter and tests/integration/events).
#pragma once

#include <nclink/adapter.hpp>
#include <nclink/dtu.hpp>
#include <nclink/testing/loopback_transport.hpp>
#include <nclink/topics.hpp>

#include "support/fake_driver.hpp"
#include "support/wait.hpp"
#ifdef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
#include <nclink/mqtt_transport.hpp>

#include "support/mosquitto_broker.hpp"
#endif

#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace nclink::test {

inline std::string test_model_path() { return std::string(NCLINK_TEST_DATA_DIR) + "/adapter-test-model.json"; }

inline std::string scratch_dir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("nclink-" + name + "-" + std::to_string(std::random_device{}()));
    std::filesystem::create_directories(dir);
    return dir.string();
}

/// Collects every message the application side receives.
class AppSide {
public:
    explicit AppSide(std::unique_ptr<Transport> link) : transport(std::move(link)) {
        transport->set_message_handler([this](const Message& m) {
            std::lock_guard<std::mutex> lock(mutex);
            inbox.push_back(m);
        });
        REQUIRE(transport->start().ok());
        REQUIRE(eventually([&] { return transport->state() == LinkState::connected; }));
    }
    // The transport's handler pushes into `inbox`: stop it (which waits for a
    // running callback) before the members below it are destroyed.
    ~AppSide() { transport->stop(std::chrono::milliseconds(0)); }
    AppSide(const AppSide&) = delete;
    AppSide& operator=(const AppSide&) = delete;

    void subscribe(const std::string& filter) {
        REQUIRE(transport->subscribe({filter}, 1).ok());
#ifdef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
        // The SUBACK comes asynchronously: wait until a probe message arrives.
        REQUIRE(eventually([&] {
            send("fixture/probe", "p");
            return eventually([&] { return !on("fixture/probe").empty(); }, std::chrono::milliseconds(100));
        }));
#endif
    }
    void send(const std::string& topic, const std::string& payload, bool retained = false) {
        REQUIRE(transport->publish(Message{topic, payload, 1, retained}).ok());
    }
    std::vector<Message> on(const std::string& topic) {
        std::lock_guard<std::mutex> lock(mutex);
        std::vector<Message> out;
        for (const auto& m : inbox)
            if (m.topic == topic) out.push_back(m);
        return out;
    }
    /// Waits for the n-th message on `topic` and returns its payload as JSON.
    Json wait(const std::string& topic, std::size_t n = 1) {
        REQUIRE(eventually([&] { return on(topic).size() >= n; }));
        return Json::parse(on(topic)[n - 1].payload);
    }
    /// Sends and waits for the next message on `reply_topic`.
    Json request(const std::string& topic, const std::string& reply_topic, const Json& payload) {
        const std::size_t before = on(reply_topic).size();
        send(topic, payload.dump());
        return wait(reply_topic, before + 1);
    }

    std::unique_ptr<Transport> transport;
    std::mutex mutex;
    std::vector<Message> inbox;
};

struct AdapterFixture {
    explicit AdapterFixture(AdapterConfig extra = {}, bool start_now = true) : config(std::move(extra)) {
        if (config.model_path.empty()) config.model_path = test_model_path();
        if (config.persistence_dir.empty()) config.persistence_dir = scratch_dir("adapter");
        config.register_timeout = std::chrono::milliseconds(200);
        driver = std::make_shared<FakeDriver>();
        app = std::make_unique<AppSide>(app_transport());
        app->subscribe("#");
        if (start_now) start();
    }
    ~AdapterFixture() {
        if (adapter) adapter->stop();
        std::error_code ec;
        std::filesystem::remove_all(config.persistence_dir, ec);
    }
#ifdef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
    std::unique_ptr<Transport> app_transport() {
        MqttOptions o;
        o.broker_url = mosquitto.url();
        o.client_id = "app";
        return make_mqtt_transport(o).value();
    }
    void start() {
        config.broker_url = mosquitto.url();  // the adapter's own MQTT transport, will and all
        adapter = std::make_unique<Adapter>(config, driver, logger);
        adapter->use_clock(clock);
#else
    std::unique_ptr<Transport> app_transport() {
        LoopbackOptions o;
        o.client_id = "app";
        return make_loopback_transport(broker, o);
    }
    void start() {
        adapter = std::make_unique<Adapter>(config, driver, logger);
        LoopbackOptions o;
        o.client_id = "adapter";
        o.last_will = Message{"Notify/State/test-dev", R"({"tid":"test-dev","state":"offline"})", 1, true};
        adapter->use_transport(make_loopback_transport(broker, o));
        adapter->use_clock(clock);
#endif
#ifdef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
        const std::size_t announced = app->on("Notify/State/test-dev").size();
#endif
        auto started = adapter->start();
        INFO((started.ok() ? std::string() : started.error().describe()));
        REQUIRE(started.ok());
        REQUIRE(eventually([&] { return adapter->state() == AdapterState::normal; }));
#ifdef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
        // The adapter's state says its SUBSCRIBE is queued, not that the
        // broker has it: a request published now could reach the broker
        // first and be delivered to nobody. The adapter subscribes before it
        // announces itself (one connection: the broker keeps the order), so
        // its online state arriving here means its requests will too, which
        // is also what a real application waits for (8.3.1).
        REQUIRE(eventually([&] {
            const auto states = app->on("Notify/State/test-dev");
            for (std::size_t i = announced; i < states.size(); ++i)
                if (Json::parse(states[i].payload).value("state", "") == "online") return true;
            return false;
        }));
#endif
    }
    Json query(const Json& ids, const std::string& ex = "app") {
        return app->request(topics::query_request("test-dev", ex), topics::query_response("test-dev", ex),
                            Json{{"@id", "q" + std::to_string(++counter)}, {"guid", "test-dev"}, {"ids", ids}});
    }
    Json set(const Json& values, const std::string& ex = "app") {
        return app->request(topics::set_request("test-dev", ex), topics::set_response("test-dev", ex),
                            Json{{"@id", "s" + std::to_string(++counter)}, {"guid", "test-dev"}, {"values", values}});
    }

    AdapterConfig config;
    Logger logger;  ///< the adapter's, from the next start()
#ifdef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
    MosquittoBroker mosquitto;
#endif
    LoopbackBroker broker;
    std::shared_ptr<ManualClock> clock = std::make_shared<ManualClock>();
    std::shared_ptr<FakeDriver> driver;
    std::unique_ptr<AppSide> app;
    std::unique_ptr<Adapter> adapter;
    int counter = 0;
};

}  // namespace nclink::test
