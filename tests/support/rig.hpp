// What the integration tests' rigs share: a started adapter, a connected
// client, the simulated mill, a scratch directory. Each feature's rig keeps
// only what is particular to it (its configuration, its helpers).
#pragma once

#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/model.hpp>
#include <nclink/mqtt_transport.hpp>
#include "sim/sim_driver.hpp"

#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>

namespace nclink::test {

/// An adapter started on `config` and in state normal (registered or not).
inline std::unique_ptr<Adapter> started_adapter(const AdapterConfig& config, std::shared_ptr<Driver> driver,
                                                std::shared_ptr<Clock> clock = nullptr) {
    auto adapter = std::make_unique<Adapter>(config, std::move(driver));
    if (clock) adapter->use_clock(std::move(clock));
    REQUIRE(adapter->start().ok());
    REQUIRE(eventually([&] { return adapter->state() == AdapterState::normal; }));
    return adapter;
}

/// A started, connected client of application `ex`. `tweak` may adjust the
/// options before the client is made (credentials, session, reconnect...).
/// It waits `timeout` (at least 10 s) for the broker connection.
inline std::unique_ptr<Client> started_client(const std::string& broker_url, const std::string& ex,
                                              std::chrono::milliseconds timeout = std::chrono::seconds(5),
                                              const std::function<void(MqttOptions&, ClientOptions&)>& tweak = {}) {
    MqttOptions mqtt;
    mqtt.broker_url = broker_url;
    ClientOptions options;
    options.ex_cid = ex;
    options.default_timeout = timeout;
    if (tweak) tweak(mqtt, options);
    auto made = Client::create(std::move(mqtt), std::move(options));
    REQUIRE(made.ok());
    auto client = std::move(made).value();
    REQUIRE(client->start().ok());
    REQUIRE(client->wait_connected(std::max<std::chrono::milliseconds>(std::chrono::seconds(10), timeout)));
    return client;
}

/// The simulated mill the examples run (models/sim-mill.json) and its device id.
inline std::string sim_mill_path() { return std::string(NCLINK_MODELS_DIR) + "/sim-mill.json"; }
inline const std::string kSimMillDevice = "nclink-sim-mill-01";

/// The simulated machine of a model file.
inline std::shared_ptr<SimDriver> sim_for(const std::string& model_path, SimOptions options = {}) {
    auto loaded = load_model_file(model_path);
    REQUIRE(loaded.ok());
    auto created = SimDriver::create(loaded.model, std::move(options));
    REQUIRE(created.ok());
    return std::move(created).value();
}

/// A fresh directory under the system's temp dir, removed with everything in it.
struct ScratchDir {
    explicit ScratchDir(const std::string& prefix)
        : path(std::filesystem::temp_directory_path() / (prefix + std::to_string(std::random_device{}()))) {}
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    std::filesystem::path path;
};

}  // namespace nclink::test
