// The "sampling" adapter service over the in-process loopback: the model's
// channels run and publish, a Probe/Set restarts them, the statistics item
// answers a Query, push mode through the Adapter, sampling.enabled.
#include "support/adapter_fixture.hpp"

#include <fstream>
#include <sstream>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

std::uint64_t rows_of(const Adapter& adapter, const std::string& id) {
    for (const auto& c : adapter.sampling_stats().channels)
        if (c.id == id) return c.rows_sampled;
    return 0;
}

/// Moves fake time in sample-interval steps, waiting for each tick's row.
void run_ticks(AdapterFixture& f, const std::string& channel, int ticks, std::chrono::milliseconds step) {
    for (int i = 0; i < ticks; ++i) {
        const auto before = rows_of(*f.adapter, channel);
        f.clock->advance(step);
        REQUIRE(eventually([&] { return rows_of(*f.adapter, channel) > before; }));
    }
}

/// Ticks on (as run_ticks) until a DTU arrives on `topic`; returns the first.
Json wait_dtu(AdapterFixture& f, const std::string& channel, const std::string& topic) {
    for (int i = 0; i < 1000 && f.app->on(topic).empty(); ++i) run_ticks(f, channel, 1, std::chrono::milliseconds(10));
    return f.app->wait(topic);
}

Json test_model() {
    std::ifstream in(test_model_path());
    std::stringstream text;
    text << in.rdbuf();
    return Json::parse(text.str());
}

}  // namespace

TEST_CASE("the model's sample channel publishes Sample DTUs with every row") {
    AdapterFixture f;
    REQUIRE(eventually([&] { return rows_of(*f.adapter, "ch1") >= 1; }));
    run_ticks(f, "ch1", 10, 10ms);
    const Json dtu = wait_dtu(f, "ch1", "Sample/test-dev/ch1");
    CHECK(dtu.at("guid") == "test-dev");
    CHECK(dtu.at("id") == "ch1");
    REQUIRE(dtu.at("data").size() == 1);  // one column: ids = [pos]
    const auto& column = dtu.at("data")[0].at("data");
    CHECK(column.size() >= 10);
    for (const auto& v : column) CHECK(v == 12.5);
    const auto stats = f.adapter->stats().features.at("sampling");
    CHECK(stats.at("channels")[0].at("id") == "ch1");
    CHECK(stats.at("channels")[0].at("rows_published").get<int>() >= 10);
    // The sampling thread's own scheduling, as it applied it at start.
    const auto& realtime = stats.at("realtime");
    CHECK(realtime.at("slice_us") == 100);
    CHECK(realtime.at("slice_granted") == f.adapter->sampling_stats().realtime.slice_granted);
    CHECK(realtime.at("fifo_priority") == 0);
}

TEST_CASE("a Probe/Set restarts the sample channels from the new model") {
    AdapterFixture f;
    REQUIRE(eventually([&] { return rows_of(*f.adapter, "ch1") >= 1; }));
    Json model = test_model();
    auto& configs = model["devices"][0]["configs"];
    configs[2] = Json{{"id", "ch2"},
                      {"type", "SAMPLE_CHANNEL"},
                      {"ids", Json::array({Json{{"id", "ovr"}}, Json{{"id", "pos"}}})},
                      {"sampleInterval", 10},
                      {"uploadInterval", 20}};
    model["devices"][0]["version"] = "1.0.1";
    const Json reply = f.app->request(topics::probe_set_request("test-dev", "app"), topics::probe_set_response("test-dev", "app"),
                                      Json{{"@id", "ps1"}, {"guid", "test-dev"}, {"probe", model}});
    REQUIRE(reply.at("code") == "OK");
    REQUIRE(eventually([&] {
        const auto s = f.adapter->sampling_stats();
        return s.channels.size() == 1 && s.channels[0].id == "ch2";
    }));
    REQUIRE(eventually([&] { return rows_of(*f.adapter, "ch2") >= 1; }));
    const Json dtu = wait_dtu(f, "ch2", "Sample/test-dev/ch2");
    REQUIRE(dtu.at("data").size() == 2);
    CHECK(dtu.at("data")[0].at("data")[0] == 100);   // ovr
    CHECK(dtu.at("data")[1].at("data")[0] == 12.5);  // pos
}

TEST_CASE("a Query of the nclink_stats item answers the adapter statistics") {
    AdapterFixture f;
    REQUIRE(eventually([&] { return rows_of(*f.adapter, "ch1") >= 1; }));
    const Json reply = f.query(Json::array({Json{{"id", "nclink_stats"}}}));
    REQUIRE(reply.at("values").size() == 1);
    const auto& item = reply.at("values")[0];
    REQUIRE(item.at("code") == "OK");
    const auto& stats = item.at("values")[0];
    CHECK(stats.contains("requests"));
    CHECK(stats.at("features").at("sampling").at("channels")[0].at("id") == "ch1");
    // keys select parts of it, as for any dict item
    const Json part = f.query(Json::array({Json{{"id", "nclink_stats"}, {"params", Json{{"keys", Json::array({"state"})}}}}}));
    CHECK(part.at("values")[0].at("code") == "OK");
}

TEST_CASE("push_channels makes a model channel push-mode through Adapter::push_channel") {
    AdapterConfig config;
    config.sampling.push_channels = {"ch1"};
    AdapterFixture f(config);
    auto ch = f.adapter->push_channel("ch1");
    REQUIRE(ch.ok());
    CHECK(f.adapter->push_channel("nope").error().code == ErrorCode::node_not_exists);
    for (int i = 0; i < 10; ++i) {
        const SampleValue v = SampleValue::float64(i);
        REQUIRE(ch.value().push(&v, 1));
    }
    CHECK(rows_of(*f.adapter, "ch1") == 10);
    // The uploader publishes every 100 ms of fake time.
    REQUIRE(eventually([&] {
        f.clock->advance(10ms);
        std::this_thread::sleep_for(1ms);
        return !f.app->on("Sample/test-dev/ch1").empty();
    }));
    const Json dtu = f.app->wait("Sample/test-dev/ch1");
    CHECK(dtu.at("data")[0].at("data") == Json::array({0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
    CHECK(f.driver->writes == 0);
}

TEST_CASE("sampling.enabled false runs no channel") {
    AdapterConfig config;
    config.sampling.enabled = false;
    AdapterFixture f(config);
    f.clock->advance(200ms);
    std::this_thread::sleep_for(50ms);
    CHECK(f.adapter->sampling_stats().channels.empty());
    CHECK(f.app->on("Sample/test-dev/ch1").empty());
    CHECK(f.adapter->push_channel("ch1").error().code == ErrorCode::unavailable);
}

TEST_CASE("model channels publish at sampling.qos, default 1, unless channel_qos says otherwise") {
    for (int configured : {-1, 0, 1}) {
        AdapterConfig config;
        if (configured >= 0) config.sampling.channel_qos["ch1"] = configured;
        else config.sampling.qos = 0;
        AdapterFixture f(config);
        REQUIRE(eventually([&] { return rows_of(*f.adapter, "ch1") >= 1; }));
        wait_dtu(f, "ch1", "Sample/test-dev/ch1");
        INFO("channel_qos " << configured);
        CHECK(f.app->on("Sample/test-dev/ch1").front().qos == (configured == 1 ? 1 : 0));
    }
    AdapterConfig all;  // the default: QoS 1 (docs/delivery.md)
    AdapterFixture f(all);
    REQUIRE(eventually([&] { return rows_of(*f.adapter, "ch1") >= 1; }));
    wait_dtu(f, "ch1", "Sample/test-dev/ch1");
    CHECK(f.app->on("Sample/test-dev/ch1").front().qos == 1);
}
