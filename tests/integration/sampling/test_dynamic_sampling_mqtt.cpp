// Dynamic sampling through the wire: the simulated mill behind an Adapter, a
// real mosquitto, the client library and `nclink sample`.
#include <nclink/adapter.hpp>
#include <nclink/client.hpp>
#include <nclink/mqtt_transport.hpp>
#include "sim/sim_driver.hpp"
#include <nclink/topics.hpp>

#include "support/cli.hpp"
#include "support/collected.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <mutex>
#include <random>
#include <sstream>

using namespace nclink;
using nclink::test::cli_built;
using nclink::test::run_cli;
using Run = nclink::test::CliRun;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::MosquittoBroker;
using nclink::test::ScratchDir;
using nclink::test::sim_for;
using nclink::test::sim_mill_path;
using nclink::test::started_adapter;
using nclink::test::started_client;
namespace fs = std::filesystem;

namespace {

const std::string kDev = nclink::test::kSimMillDevice;

struct Rig : nclink::test::SimMillRig {
    fs::path root = scratch.path;
    std::shared_ptr<SimDriver> sim;

    Rig() : SimMillRig({}, "nclink-itest-dynamic-") {
        config.persistence_dir = (root / "state").string();
        config.register_timeout = 200ms;
        config.sampling.max_dynamic_channels = 2;
        sim = sim_for(config.model_path);
        driver = sim;
        start();
        client = make_client("mes-1");
    }
    Json dynamic_stats() { return adapter->stats().features.at("sampling").at("dynamic"); }
};

using Rows = nclink::test::Collected<SampleDtu>;

}  // namespace

TEST_CASE("a client registers a dynamic channel on the simulated mill receives its rows and unregisters it") {
    Rig rig;
    Rows rows;
    auto channel = rig.client->register_sampling(kDev, {"x_position", "spindle_speed", "status"}, 10ms, 50ms,
                                                 [&](const SampleDtu& d) { rows.add(d); });
    REQUIRE(channel.ok());
    CHECK(channel->dev == kDev);
    CHECK(channel->id.rfind("dyn", 0) == 0);
    REQUIRE(eventually([&] { return rows.size() >= 3; }));
    const SampleDtu dtu = rows.at(1);
    CHECK(dtu.id == channel->id);
    CHECK(dtu.guid == kDev);
    REQUIRE(dtu.data.size() == 3);  // one column per id, in order
    CHECK(dtu.data[0].size() == dtu.data[1].size());
    CHECK(dtu.data[0].size() >= 1);
    CHECK(dtu.data[2][0].is_string());  // STATUS text
    CHECK_FALSE(Client::is_replayed(dtu));
    CHECK(rig.dynamic_stats()["owners"][channel->id] == "mes-1");

    // Another application cannot remove it; the owner can, once.
    auto other = rig.make_client("intruder");
    auto refused = other->unregister_sampling(Client::SamplingChannel{kDev, channel->id, 0});
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::permission_denied);
    REQUIRE(rig.client->unregister_sampling(*channel).ok());
    auto again = rig.client->unregister_sampling(*channel);
    REQUIRE_FALSE(again.ok());
    CHECK(again.error().code == ErrorCode::node_not_exists);
    CHECK(rig.dynamic_stats()["channels"] == 0);
}

TEST_CASE("dynamic registration refusals reach the client as errors with the table-19 code") {
    Rig rig;
    auto unknown = rig.client->register_sampling(kDev, {"x_position", "warp_drive"}, 10ms, 50ms, {});
    REQUIRE_FALSE(unknown.ok());
    CHECK(unknown.error().code == ErrorCode::node_not_exists);
    auto intervals = rig.client->register_sampling(kDev, {"x_position"}, 50ms, 10ms, {});
    REQUIRE_FALSE(intervals.ok());
    CHECK(intervals.error().code == ErrorCode::attribute_error);
    REQUIRE(rig.client->register_sampling(kDev, {"x_position"}, 10ms, 100ms, {}).ok());
    REQUIRE(rig.client->register_sampling(kDev, {"x_position"}, 10ms, 100ms, {}).ok());
    auto full = rig.client->register_sampling(kDev, {"x_position"}, 10ms, 100ms, {});
    REQUIRE_FALSE(full.ok());
    CHECK(full.error().code == ErrorCode::insufficient_dynamic_sampling);
}

TEST_CASE("dynamic channels of a client that stops are released when it goes offline") {
    Rig rig;
    auto quitter = rig.make_client("quitter");
    REQUIRE(quitter->register_sampling(kDev, {"x_position"}, 10ms, 50ms, {}).ok());
    REQUIRE(rig.dynamic_stats()["channels"] == 1);
    // What an agent (or the application's last will) announces.
    MqttOptions o;
    o.broker_url = rig.broker.url();
    o.client_id = "announcer";
    auto announcer = make_mqtt_transport(o).value();
    REQUIRE(announcer->start().ok());
    REQUIRE(eventually([&] { return announcer->state() == LinkState::connected; }));
    quitter->stop();
    REQUIRE(announcer->publish(Message{topics::notify_state("quitter"), R"({"tid":"quitter","state":"offline"})", 1, false}).ok());
    REQUIRE(eventually([&] { return rig.dynamic_stats()["channels"] == 0; }));
    CHECK(rig.dynamic_stats()["released"] == 1);
    announcer->stop(0ms);
}

TEST_CASE("nclink sample prints the rows of a dynamic channel and unregisters it") {
    if (!cli_built()) {
        WARN("bin/nclink not built (NCLINK_BUILD_TOOLS=OFF): skipped");
        return;
    }
    Rig rig;
    const Run run = run_cli("sample --broker " + rig.broker.url() + " " + kDev +
                            " x_position spindle_speed --sample-ms 10 --upload-ms 20 --count 6");
    INFO(run.out);
    CHECK(run.status == 0);
    std::istringstream lines(run.out);
    std::string line;
    std::vector<std::string> all;
    while (std::getline(lines, line)) all.push_back(line);
    REQUIRE(all.size() == 7);  // header + 6 rows
    CHECK(all[0].find("x_position") != std::string::npos);
    CHECK(all[0].find("spindle_speed") != std::string::npos);
    for (std::size_t i = 1; i < all.size(); ++i) CHECK(all[i].find('Z') == 23);  // ISO time first
    REQUIRE(eventually([&] { return rig.dynamic_stats()["channels"] == 0; }));   // unregistered on the way out
    CHECK(rig.dynamic_stats()["unregistered"] == 1);

    const Run bad = run_cli("sample --broker " + rig.broker.url() + " " + kDev + " nope --sample-ms 10 --upload-ms 20");
    CHECK(bad.status == 1);
    const Run usage = run_cli("sample " + kDev + " x_position --sample-ms 10");
    CHECK(usage.status == 2);
}
