// Modbus RTU in a gateway, end to end: two gateway machines (two slave
// addresses) on one serial line (a socat pty pair, support/rtu_line.hpp),
// configured from examples/modbus/gateway-rtu.json (the plugin, the line and
// the map in `defaults`, each machine its slave_id), served through a real mosquitto to an NC-Link
// application: Query and Set per machine, a slave that goes silent (203, then
// recovery) while the other keeps answering, and an answer with a bad CRC.
#include <catch2/catch.hpp>

#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/rtu_line.hpp"
#include "support/wait.hpp"

#include <nclink/client.hpp>
#include <nclink/gateway.hpp>

#include <fstream>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

std::string example(const std::string& name) { return std::string(NCLINK_MODELS_DIR) + "/../examples/modbus/" + name; }

/// examples/modbus/gateway-rtu.json (the file docs/gateway.md shows) with
/// this broker, this line, its paths made absolute and quick backoffs.
/// Sampling is off so that only the test's Queries and Sets ask the slaves:
/// the Query that meets a silent slave or a damaged answer is then known.
std::string write_gateway_file(const std::string& dir, const std::string& broker, const std::string& device) {
    std::ifstream in(example("gateway-rtu.json"));
    Json file = Json::parse(in);
    Json& defaults = file["defaults"];
    defaults["broker"]["url"] = broker;
    defaults["model"] = example("plc-lathe.json");
    defaults["driver"]["plugin"] = std::string(NCLINK_BINARY_DIR) + "/lib/nclink-modbus.so";
    defaults["driver"]["config"]["device"] = device;
    defaults["driver"]["config"]["backoff_ms"] = Json{{"min", 50}, {"max", 200}};
    defaults["register_timeout_ms"] = 500;
    defaults["sampling"]["enabled"] = false;
    const std::string path = dir + "/gateway.json";
    std::ofstream(path) << file.dump(2);
    return path;
}

struct RtuGatewayRig {
    MosquittoBroker broker;
    PtyLine line;
    RtuSlaves slaves{line.slave_end(), {1, 2}};
    std::unique_ptr<Gateway> gateway;
    std::unique_ptr<Client> client;

    RtuGatewayRig() {
        for (int slave : {1, 2}) {
            slaves.set_holding(slave, 0, 1);                                        // status running
            slaves.set_holding(slave, 3, static_cast<std::uint16_t>(100 + slave));  // feed_override
            slaves.set_input(slave, 4, 0);
            slaves.set_input(slave, 5, static_cast<std::uint16_t>(1000 * slave));  // spindle_speed, scale 0.1
        }
        auto config = load_gateway_config(write_gateway_file(line.dir(), broker.url(), line.driver_end()));
        INFO((config.ok() ? std::string() : config.error().message));
        REQUIRE(config.ok());
        gateway = std::make_unique<Gateway>(std::move(config).value());
        auto started = gateway->start();
        INFO((started.ok() ? std::string() : started.error().message));
        REQUIRE(started.ok());
        REQUIRE(eventually(
            [&] {
                for (const auto& m : gateway->machines())
                    if (m.state != AdapterState::normal) return false;
                return true;
            },
            30s));
        client = started_client(broker.url(), "mes-rtu", 5s);
    }
    ~RtuGatewayRig() {
        if (client) client->stop();
        if (gateway) gateway->stop();
    }

    /// One item's Query answer: the value, or the error code.
    std::pair<Json, int> query(const std::string& guid, const std::string& id) {
        auto r = client->query(guid, {QueryItem{id, std::nullopt}});
        REQUIRE(r.ok());
        const auto& item = r->at(0);
        if (!item.status.ok) return {Json(nullptr), item.status.error.value_or(0)};
        return {(*item.values)[0], 0};
    }
};

}  // namespace

TEST_CASE("two gateway machines on one RTU line answer Query and Set as their own slaves") {
    RtuGatewayRig rig;
    CHECK(rig.query("plc-lathe-rtu-1", "feed_override").first == 101);
    CHECK(rig.query("plc-lathe-rtu-2", "feed_override").first == 102);
    CHECK(rig.query("plc-lathe-rtu-1", "status").first == "running");
    CHECK(rig.query("plc-lathe-rtu-2", "spindle_speed").first.get<double>() == Approx(200.0));

    auto set = rig.client->set("plc-lathe-rtu-2", {SetItem{"feed_override", Json{{"value", 77}}, std::nullopt, std::nullopt}});
    REQUIRE(set.ok());
    REQUIRE(set->at(0).status.ok);
    CHECK(rig.slaves.holding(2, 3) == 77);
    CHECK(rig.slaves.holding(1, 3) == 101);
    CHECK(rig.query("plc-lathe-rtu-2", "feed_override").first == 77);
    CHECK(rig.slaves.bad_frames() == 0);
}

TEST_CASE("a silent RTU slave answers 203 and comes back, the other machine on its line keeps answering") {
    RtuGatewayRig rig;
    REQUIRE(rig.query("plc-lathe-rtu-2", "feed_override").first == 102);
    rig.slaves.set_silent(2, true);
    // The Query that meets the silent slave: Timeout (203) from the driver.
    CHECK(rig.query("plc-lathe-rtu-2", "feed_override").second == 203);
    CHECK(rig.query("plc-lathe-rtu-1", "feed_override").first == 101);

    rig.slaves.set_silent(2, false);
    rig.slaves.set_holding(2, 3, 103);
    CHECK(eventually([&] { return rig.query("plc-lathe-rtu-2", "feed_override").first == 103; }, 20s));
}

TEST_CASE("an RTU answer with a bad CRC fails that Query alone, and the next one is answered") {
    RtuGatewayRig rig;
    REQUIRE(rig.query("plc-lathe-rtu-1", "feed_override").first == 101);
    rig.slaves.damage_next_answer(1);
    CHECK(rig.query("plc-lathe-rtu-1", "feed_override").second == 202);
    CHECK(rig.query("plc-lathe-rtu-1", "feed_override").first == 101);
    CHECK(rig.query("plc-lathe-rtu-2", "feed_override").first == 102);
}
