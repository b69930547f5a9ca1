// The Modbus TCP driver against a real Modbus server (libmodbus' server side,
// test_plc.hpp): reads batched, values scaled, writes, read-only items, and a
// PLC that disappears (DEV_UNREACHABLE, backoff on an injected clock) and comes back.
#include <catch2/catch.hpp>

#include "modbus/modbus_driver.hpp"
#include "support/driver_calls.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/test_plc.hpp"

using namespace nclink;
using namespace nclink::modbus;
using nclink::test::TestPlc;

namespace {

struct Fixture {
    int port = nclink::test::free_loopback_port();
    TestPlc plc{port};
    std::chrono::steady_clock::time_point now = std::chrono::steady_clock::now();
    ModbusDriver driver{std::nullopt, [this] { return now; }};

    Fixture() {
        Json config = Json::parse(R"({"host":"127.0.0.1","timeout_ms":300,"backoff_ms":{"min":100,"max":400},"points":{
            "spindle_speed":{"table":"holding","address":10,"type":"int32","scale":0.1},
            "feed_override":{"table":"holding","address":12},
            "status":{"table":"holding","address":13,"enum":{"0":"free","1":"running"}},
            "x_position":{"table":"input","address":0,"type":"float32"},
            "door_open":{"table":"coil","address":2},
            "estop":{"table":"discrete_input","address":0}}})");
        config["port"] = port;
        DriverContext ctx;
        ctx.config = config;
        REQUIRE(driver.open(ctx).ok());
    }
    ~Fixture() { driver.close(); }

    std::vector<Result<Json>> read(const std::vector<std::string>& ids) { return test::read_points(driver, ids); }

    Result<void> write(const std::string& id, Json value) { return test::write_point(driver, id, std::move(value)); }
};

}  // namespace

TEST_CASE_METHOD(Fixture, "values come from the PLC's tables, scaled, one request per batch") {
    plc.set_holding(10, 0x0001);
    plc.set_holding(11, 0x86A0);  // 100000 -> 10000.0 rpm at scale 0.1
    plc.set_holding(12, 80);
    plc.set_holding(13, 1);
    plc.set_input(0, 0x42F6);  // 123.0f = 0x42F60000
    plc.set_input(1, 0x0000);
    plc.set_coil(2, true);
    plc.set_discrete(0, false);
    CHECK(driver.link().state == MachineLink::connected);
    const int before = plc.requests();
    auto r = read({"spindle_speed", "feed_override", "status", "x_position", "door_open", "estop"});
    for (auto& v : r) REQUIRE(v.ok());
    CHECK(r[0].value().get<double>() == Approx(10000.0));
    CHECK(r[1].value() == 80);
    CHECK(r[2].value() == "running");
    CHECK(r[3].value().get<double>() == Approx(123.0));
    CHECK(r[4].value() == true);
    CHECK(r[5].value() == false);
    // Holding 10..13 in one request, input 0..1, coil 2, discrete 0: four.
    CHECK(plc.requests() - before == 4);
}

TEST_CASE_METHOD(Fixture, "an item outside the map answers Unavailable, the others are read") {
    plc.set_holding(12, 55);
    auto r = read({"no_such_item", "feed_override"});
    REQUIRE_FALSE(r[0].ok());
    CHECK(r[0].error().code == ErrorCode::unavailable);
    CHECK_THAT(r[0].error().message, Catch::Contains("not in the driver's map"));
    CHECK(r[1].value() == 55);
}

TEST_CASE_METHOD(Fixture, "writes reach the registers and coils, inputs are refused") {
    REQUIRE(write("spindle_speed", Json(1234.5)).ok());
    CHECK(plc.holding(10) == 0);
    CHECK(plc.holding(11) == 12345);
    REQUIRE(write("status", Json("running")).ok());
    CHECK(plc.holding(13) == 1);
    REQUIRE(write("door_open", Json(true)).ok());
    CHECK(plc.coil(2));
    auto refused = write("x_position", Json(1.0));
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::permission_denied);
    auto range = write("feed_override", Json(70000));
    REQUIRE_FALSE(range.ok());
    CHECK(range.error().code == ErrorCode::out_of_range);
}

TEST_CASE_METHOD(Fixture, "a PLC that disappears answers DEV_UNREACHABLE, backs off, and is read again when it is back") {
    plc.set_holding(12, 42);
    REQUIRE(read({"feed_override"})[0].ok());
    plc.stop();

    // The request on the dead connection fails: Unavailable, DEV_UNREACHABLE.
    auto r = read({"feed_override", "x_position"});
    for (auto& v : r) {
        REQUIRE_FALSE(v.ok());
        CHECK(v.error().code == ErrorCode::unavailable);
        CHECK_THAT(v.error().message, Catch::Contains("DEV_UNREACHABLE"));
    }
    CHECK(driver.link().state == MachineLink::disconnected);
    CHECK_THAT(driver.link().reason, Catch::Contains("DEV_UNREACHABLE"));

    // Within the backoff no connect is tried (the clock stands still).
    const auto connects = driver.stats().connects;
    const auto failures = driver.stats().failures;
    r = read({"feed_override"});
    CHECK_THAT(r[0].error().message, Catch::Contains("next attempt in"));
    CHECK(driver.stats().failures == failures);

    // After the backoff a connect is tried, fails (still gone), and the wait
    // doubles. Once it is due, link() no longer says disconnected: the SDK
    // calls read() again, which is where the driver reconnects.
    now += std::chrono::milliseconds(150);
    CHECK(driver.link().state == MachineLink::unknown);
    r = read({"feed_override"});
    REQUIRE_FALSE(r[0].ok());
    CHECK(driver.stats().failures == failures + 1);
    now += std::chrono::milliseconds(150);
    r = read({"feed_override"});
    CHECK_THAT(r[0].error().message, Catch::Contains("next attempt in"));

    // Back: the next attempt after the backoff connects and reads.
    plc.start();
    plc.set_holding(12, 43);
    now += std::chrono::milliseconds(500);
    r = read({"feed_override"});
    REQUIRE(r[0].ok());
    CHECK(r[0].value() == 43);
    CHECK(driver.link().state == MachineLink::connected);
    CHECK(driver.stats().connects == connects + 1);

    // A write while the PLC is gone answers DEV_UNREACHABLE too.
    plc.stop();
    auto w = write("feed_override", Json(10));
    REQUIRE_FALSE(w.ok());
    CHECK(w.error().code == ErrorCode::unavailable);
    CHECK_THAT(w.error().message, Catch::Contains("DEV_UNREACHABLE"));
}

TEST_CASE("a PLC that is not there at start does not stop the adapter from starting") {
    const int port = nclink::test::free_loopback_port();
    ModbusDriver driver;
    DriverContext ctx;
    ctx.config = Json::parse(R"({"host":"127.0.0.1","timeout_ms":200,"points":{"a":{"table":"holding","address":0}}})");
    ctx.config["port"] = port;
    CHECK(driver.open(ctx).ok());
    CHECK(driver.link().state == MachineLink::disconnected);
    std::vector<PointRef> points{PointRef{"a", DataKind::single}};
    std::vector<Result<Json>> results(1, make_error(ErrorCode::unavailable, "not read"));
    driver.read(points, results);
    CHECK_THAT(results[0].error().message, Catch::Contains("DEV_UNREACHABLE"));
}

TEST_CASE("a bad map stops open() with the located problem") {
    ModbusDriver driver;
    DriverContext ctx;
    ctx.config = Json::parse(R"({"points":{"a":{"table":"holding"}}})");
    auto r = driver.open(ctx);
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message, Catch::Contains("points/a/address: missing"));
}
