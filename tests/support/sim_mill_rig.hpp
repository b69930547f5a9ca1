// The one integration fixture: a real mosquitto on a free loopback port, an
// adapter serving the simulated mill (or a driver the test brings), and
// clients of any application id. A test (or its own rig deriving from this
// one) adjusts `config` and `driver`, then calls start(). Teardown order is
// fixed here, once: clients, then the adapter, then the broker.
#pragma once

#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"

#include <nclink/adapter.hpp>
#include <nclink/client.hpp>

#include <catch2/catch.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nclink::test {

struct SimMillRig {
    explicit SimMillRig(MosquittoOptions broker_options = {}, const std::string& scratch_prefix = "nclink-itest-")
        : broker(broker_options), scratch(scratch_prefix) {
        config.broker_url = broker.url();
        config.model_path = sim_mill_path();
        config.register_timeout = std::chrono::milliseconds(500);
    }
    virtual ~SimMillRig() { stop(); }
    SimMillRig(const SimMillRig&) = delete;
    SimMillRig& operator=(const SimMillRig&) = delete;

    /// Starts the adapter on `config` with `driver` (the simulated mill of
    /// config.model_path when none was set) and waits for state normal.
    Adapter& start(std::shared_ptr<Clock> clock = nullptr) {
        if (!driver) driver = sim_for(config.model_path);
        adapter = started_adapter(config, driver, std::move(clock));
        return *adapter;
    }
    /// A started client of application `ex`, with a client id of its own and
    /// quick reconnects; `tweak` adjusts the options further.
    std::unique_ptr<Client> make_client(const std::string& ex, std::chrono::milliseconds timeout = std::chrono::seconds(5),
                                        const std::function<void(MqttOptions&, ClientOptions&)>& tweak = {}) {
        return started_client(broker.url(), ex, timeout, [&](MqttOptions& m, ClientOptions& o) {
            m.client_id = "nclink-itest-" + ex;
            m.reconnect_min = std::chrono::milliseconds(50);
            m.reconnect_max = std::chrono::milliseconds(300);
            if (tweak) tweak(m, o);
        });
    }
    /// Stops the clients the test keeps in `client`, then the adapter.
    void stop() {
        if (client) client->stop();
        if (adapter) adapter->stop(std::chrono::milliseconds(0));
    }

    /// Query of one whole item through `client`; the item must answer OK.
    Json query_one(const std::string& id, Json params = nullptr) {
        QueryItem item{id, params.is_null() ? std::nullopt : std::optional<Json>(std::move(params))};
        auto results = client->query(device(), {item});
        REQUIRE(results.ok());
        INFO(id);
        REQUIRE(results->at(0).status.ok);
        return (*results->at(0).values)[0];
    }
    /// Set of one item through `client`; the item must answer OK.
    void set_one(const std::string& id, Json params) {
        auto results = client->set(device(), {SetItem{id, std::move(params), std::nullopt, std::nullopt}});
        REQUIRE(results.ok());
        INFO(id);
        REQUIRE(results->at(0).status.ok);
    }
    std::string device() const { return adapter ? adapter->dev_uuid() : kSimMillDevice; }

    MosquittoBroker broker;
    ScratchDir scratch;
    AdapterConfig config;            ///< preset: this broker, the sim mill, quick registration retries
    std::shared_ptr<Driver> driver;  ///< null: the simulated mill of config.model_path
    std::unique_ptr<Adapter> adapter;
    std::unique_ptr<Client> client;  ///< the test's main application, stopped before the adapter
};

}  // namespace nclink::test
