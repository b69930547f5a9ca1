// The Modbus TCP driver in an adapter, end to end: a real Modbus server (the
// PLC), the adapter configured from examples/modbus (the map users copy), a
// real mosquitto, and an NC-Link application's Query and Set.
#include <catch2/catch.hpp>

#include "modbus/modbus_driver.hpp"
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"
#include "support/test_plc.hpp"

#include <fstream>

using namespace nclink;
using nclink::test::TestPlc;

namespace {

std::string example(const std::string& name) { return std::string(NCLINK_MODELS_DIR) + "/../examples/modbus/" + name; }

Json example_map(int port) {
    std::ifstream in(example("adapter.json"));
    Json adapter = Json::parse(in);
    Json map = adapter["driver"]["config"];
    map["port"] = port;
    map["backoff_ms"] = Json{{"min", 50}, {"max", 200}};
    return map;
}

struct ModbusRig : nclink::test::SimMillRig {
    int port = nclink::test::free_loopback_port();
    TestPlc plc{port};

    ModbusRig() {
        config.model_path = example("plc-lathe.json");
        config.driver_config = example_map(port);
        driver = std::make_shared<modbus::ModbusDriver>();
        plc.set_holding(0, 1);  // status running
        plc.set_holding(1, 0);
        plc.set_holding(2, 17);    // part_count 17 (uint32, big word order)
        plc.set_holding(3, 100);   // feed_override
        plc.set_input(0, 0x42C8);  // x_position 100.0f
        plc.set_input(1, 0x0000);
        plc.set_input(4, 0);
        plc.set_input(5, 12000);    // spindle_speed 1200.0 (scale 0.1)
        plc.set_discrete(0, true);  // door_closed
        start();
        client = make_client("mes-modbus");
    }
    ~ModbusRig() override { stop(); }
};

}  // namespace

TEST_CASE("Query answers the PLC's registers through the map") {
    ModbusRig rig;
    CHECK(rig.device() == "plc-lathe-01");
    CHECK(rig.query_one("status") == "running");
    CHECK(rig.query_one("part_count") == "17");  // PART_COUNT has string values (table 13): "text": true
    CHECK(rig.query_one("x_position").get<double>() == Approx(100.0));
    CHECK(rig.query_one("spindle_speed").get<double>() == Approx(1200.0));
    CHECK(rig.query_one("door_closed") == true);
}

TEST_CASE("Set of a setable item writes the PLC's holding register") {
    ModbusRig rig;
    rig.set_one("feed_override", Json{{"value", 55}});
    CHECK(rig.plc.holding(3) == 55);
    CHECK(rig.query_one("feed_override") == 55);
}

TEST_CASE("a PLC that goes away answers Unavailable, and its values return with it") {
    ModbusRig rig;
    // The PLC answers first (a loaded box may stretch one read past the map's
    // 500 ms timeout: that is a 203, not what this test is about).
    REQUIRE(nclink::test::eventually(
        [&] {
            auto first = rig.client->query(rig.device(), {QueryItem{"feed_override", std::nullopt}});
            return first.ok() && first->at(0).status.ok && (*first->at(0).values)[0] == 100;
        },
        std::chrono::seconds(20)));
    rig.plc.stop();
    auto gone = rig.client->query(rig.device(), {QueryItem{"feed_override", std::nullopt}});
    REQUIRE(gone.ok());
    REQUIRE_FALSE(gone->at(0).status.ok);
    CHECK(gone->at(0).status.error == 202);
    rig.plc.start();
    rig.plc.set_holding(3, 90);
    CHECK(nclink::test::eventually(
        [&] {
            auto back = rig.client->query(rig.device(), {QueryItem{"feed_override", std::nullopt}});
            return back.ok() && back->at(0).status.ok && (*back->at(0).values)[0] == 90;
        },
        std::chrono::seconds(20)));
}
