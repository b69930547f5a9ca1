// The simulated mill's sample channels through a real mosquitto: a plain MQTT
// subscriber receives Sample DTUs on Sample/{dev}/{channel}, with the model's
// column count, equal-length columns, contiguous rows, and every sampled row
// delivered.
#include <nclink/adapter.hpp>
#include <nclink/mqtt_transport.hpp>
#include "sim/sim_driver.hpp"
#include <nclink/topics.hpp>

#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <mutex>

using namespace nclink;
using nclink::test::eventually;
using nclink::test::MosquittoBroker;
using nclink::test::sim_mill_path;

namespace {

const std::string kDev = nclink::test::kSimMillDevice;

struct Received {
    std::mutex mutex;
    std::map<std::string, std::vector<Json>> by_topic;
    std::size_t rows(const std::string& topic) {
        std::lock_guard<std::mutex> lock(mutex);
        std::size_t n = 0;
        for (const auto& d : by_topic[topic]) n += d.at("data").at(0).at("data").size();
        return n;
    }
};

std::uint64_t published(const Adapter& adapter, const std::string& id) {
    for (const auto& c : adapter.sampling_stats().channels)
        if (c.id == id) return c.rows_published;
    return 0;
}

}  // namespace

TEST_CASE("the mill's channels arrive on Sample/dev/channel with every row") {
    MosquittoBroker broker;
    Received received;
    MqttOptions sub_options;
    sub_options.broker_url = broker.url();
    sub_options.client_id = "sample-subscriber";
    auto subscriber = make_mqtt_transport(sub_options).value();
    subscriber->set_message_handler([&](const Message& m) {
        std::lock_guard<std::mutex> lock(received.mutex);
        received.by_topic[m.topic].push_back(Json::parse(m.payload));
    });
    REQUIRE(subscriber->subscribe({"Sample/" + kDev + "/#"}, 0).ok());
    REQUIRE(subscriber->start().ok());
    REQUIRE(eventually([&] { return subscriber->state() == LinkState::connected; }));

    AdapterConfig config;
    config.model_path = sim_mill_path();
    config.broker_url = broker.url();
    config.register_timeout = std::chrono::milliseconds(500);
    const auto model = load_model_file(sim_mill_path()).model;
    REQUIRE(model);
    auto adapter = std::make_unique<Adapter>(config, SimDriver::create(model).value());
    REQUIRE(adapter->start().ok());

    const std::string fast = topics::sample(kDev, "ch_fast");
    const std::string slow = topics::sample(kDev, "ch_slow");
    // ch_slow publishes every second: two DTUs of it, and ~20 of ch_fast.
    REQUIRE(eventually([&] { return received.rows(slow) >= 15; }, std::chrono::seconds(20)));
    adapter->stop();  // publishes what the rings still hold, then flushes
    const auto stats = adapter->sampling_stats();
    REQUIRE(eventually([&] { return received.rows(fast) == published(*adapter, "ch_fast"); }));
    REQUIRE(eventually([&] { return received.rows(slow) == published(*adapter, "ch_slow"); }));
    subscriber->stop(std::chrono::milliseconds(0));

    const std::map<std::string, std::pair<std::size_t, std::int64_t>> expected = {
        {fast, {model->channel("ch_fast")->ids.size(), 1}}, {slow, {model->channel("ch_slow")->ids.size(), 100}}};
    for (const auto& [topic, shape] : expected) {
        INFO(topic);
        const auto& dtus = received.by_topic[topic];
        REQUIRE(dtus.size() >= 2);
        std::int64_t next_begin = -1;
        for (const auto& d : dtus) {
            CHECK(d.at("guid") == kDev);
            const auto& data = d.at("data");
            REQUIRE(data.size() == shape.first);  // one column per id of the channel
            const std::size_t rows = data.at(0).at("data").size();
            REQUIRE(rows > 0);
            for (const auto& column : data) REQUIRE(column.at("data").size() == rows);
            const std::int64_t begin = std::stoll(d.at("beginTime").get<std::string>());
            if (next_begin >= 0) CHECK(begin == next_begin);  // no row missing between DTUs
            next_begin = begin + static_cast<std::int64_t>(rows) * shape.second;
        }
    }
    for (const auto& c : stats.channels) {
        INFO(c.id);
        CHECK(c.drops == 0);
        CHECK(c.skipped_ticks == 0);
        CHECK(c.rows_published == c.rows_sampled);
    }
}
