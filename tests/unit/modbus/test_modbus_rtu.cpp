// The Modbus driver on an RTU serial line, end to end over a pseudo-terminal
// pair (socat) against simulated slaves (support/rtu_line.hpp): reads and
// writes, two machines sharing one line, a slave that stops answering (203,
// backoff, recovery), an answer with a bad CRC, a slow slave's late answer,
// an answer that stalls mid-frame (byte timeout),
// the line's turns in order,
// and the plugin's drivers sharing a line.
#include <catch2/catch.hpp>

#include "modbus/modbus_bus.hpp"
#include "modbus/modbus_driver.hpp"
#include "support/driver_calls.hpp"
#include "support/rtu_line.hpp"
#include "support/wait.hpp"

#include <nclink/driver_plugin_loader.hpp>

#include <modbus.h>

#include <condition_variable>
#include <thread>

using namespace nclink;
using namespace nclink::modbus;
using nclink::test::PtyLine;
using nclink::test::RtuSlaves;

namespace {

Json rtu_map(const std::string& device, int slave) {
    Json config = Json::parse(R"({"baud":19200,"parity":"E","timeout_ms":300,"byte_timeout_ms":50,
        "backoff_ms":{"min":100,"max":400},"points":{
        "spindle_speed":{"table":"holding","address":10,"type":"int32","scale":0.1},
        "feed_override":{"table":"holding","address":12},
        "status":{"table":"holding","address":13,"enum":{"0":"free","1":"running"}},
        "x_position":{"table":"input","address":0,"type":"float32"},
        "door_open":{"table":"coil","address":2},
        "estop":{"table":"discrete_input","address":0},
        "beyond":{"table":"holding","address":300}}})");
    config["device"] = device;
    config["slave_id"] = slave;
    return config;
}

/// One machine: a driver for one slave of the line, on an injected clock.
struct Machine {
    std::chrono::steady_clock::time_point now = std::chrono::steady_clock::now();
    ModbusDriver driver;

    Machine(const std::string& device, int slave, std::shared_ptr<BusRegistry> buses)
        : driver(
              std::nullopt, [this] { return now; }, std::move(buses)) {
        DriverContext ctx;
        ctx.config = rtu_map(device, slave);
        auto opened = driver.open(ctx);
        INFO((opened.ok() ? std::string() : opened.error().message));
        REQUIRE(opened.ok());
    }
    ~Machine() { driver.close(); }

    std::vector<Result<Json>> read(const std::vector<std::string>& ids) { return test::read_points(driver, ids); }

    Result<void> write(const std::string& id, Json value) { return test::write_point(driver, id, std::move(value)); }
};

struct Line {
    PtyLine pty;
    RtuSlaves slaves{pty.slave_end(), {1, 2}};
    std::shared_ptr<BusRegistry> buses = std::make_shared<BusRegistry>();
};

}  // namespace

TEST_CASE("RTU: the mapped items are read from and written to a slave on the serial line") {
    Line line;
    line.slaves.set_holding(1, 10, 0x0001);
    line.slaves.set_holding(1, 11, 0x86A0);  // 100000 -> 10000.0 rpm at scale 0.1
    line.slaves.set_holding(1, 12, 80);
    line.slaves.set_holding(1, 13, 1);
    line.slaves.set_input(1, 0, 0x42F6);  // 123.0f
    line.slaves.set_input(1, 1, 0x0000);
    line.slaves.set_coil(1, 2, true);
    line.slaves.set_discrete(1, 0, false);
    Machine m(line.pty.driver_end(), 1, line.buses);
    CHECK(m.driver.info().name == "modbus-rtu");

    const int before = line.slaves.requests(1);
    auto r = m.read({"spindle_speed", "feed_override", "status", "x_position", "door_open", "estop"});
    for (auto& v : r) {
        INFO((v.ok() ? std::string() : v.error().message));
        REQUIRE(v.ok());
    }
    CHECK(r[0].value().get<double>() == Approx(10000.0));
    CHECK(r[1].value() == 80);
    CHECK(r[2].value() == "running");
    CHECK(r[3].value().get<double>() == Approx(123.0));
    CHECK(r[4].value() == true);
    CHECK(r[5].value() == false);
    // Batched as on TCP: holding 10..13, input 0..1, coil 2, discrete 0.
    CHECK(line.slaves.requests(1) - before == 4);
    CHECK(m.driver.link().state == MachineLink::connected);

    REQUIRE(m.write("spindle_speed", Json(1234.5)).ok());
    CHECK(line.slaves.holding(1, 10) == 0);
    CHECK(line.slaves.holding(1, 11) == 12345);
    REQUIRE(m.write("status", Json("free")).ok());
    CHECK(line.slaves.holding(1, 13) == 0);
    REQUIRE(m.write("door_open", Json(false)).ok());
    CHECK_FALSE(line.slaves.coil(1, 2));
    auto reread = m.read({"spindle_speed", "status", "door_open"});
    CHECK(reread[0].value().get<double>() == Approx(1234.5));
    CHECK(reread[1].value() == "free");
    CHECK(reread[2].value() == false);

    // A register the slave does not have: its exception answers 202 for that
    // item; the slave is there, so the machine stays connected.
    auto refused = m.read({"beyond", "feed_override"});
    REQUIRE_FALSE(refused[0].ok());
    CHECK(refused[0].error().code == ErrorCode::unavailable);
    CHECK_THAT(refused[0].error().message, Catch::Contains("the PLC refused the read"));
    CHECK(refused[1].value() == 80);
    auto w = m.write("beyond", Json(1));
    REQUIRE_FALSE(w.ok());
    CHECK(w.error().code == ErrorCode::permission_denied);
    CHECK(m.driver.link().state == MachineLink::connected);
}

TEST_CASE("RTU: two machines on one serial line share it and each reads its own slave") {
    Line line;
    line.slaves.set_holding(1, 12, 11);
    line.slaves.set_holding(2, 12, 22);
    Machine a(line.pty.driver_end(), 1, line.buses);
    Machine b(line.pty.driver_end(), 2, line.buses);
    // One line, opened once.
    REQUIRE(a.driver.bus());
    CHECK(a.driver.bus() == b.driver.bus());
    CHECK(a.driver.bus()->stats().opens == 1);

    CHECK(a.read({"feed_override"})[0].value() == 11);
    CHECK(b.read({"feed_override"})[0].value() == 22);

    // Both machines read at once from their own threads (as two gateway
    // machines' driver workers do): every answer is the right slave's.
    std::atomic<int> wrong{0};
    auto reader = [&](Machine& m, int expected) {
        for (int i = 0; i < 40; ++i) {
            auto r = m.read({"feed_override", "door_open"});
            if (!r[0].ok() || r[0].value() != expected || !r[1].ok()) ++wrong;
        }
    };
    std::thread ta(reader, std::ref(a), 11);
    std::thread tb(reader, std::ref(b), 22);
    ta.join();
    tb.join();
    CHECK(wrong == 0);
    CHECK(line.slaves.bad_frames() == 0);
    CHECK(a.driver.bus()->stats().opens == 1);
    // A write of one machine lands at its own slave only.
    REQUIRE(b.write("feed_override", Json(33)).ok());
    CHECK(line.slaves.holding(2, 12) == 33);
    CHECK(line.slaves.holding(1, 12) == 11);
}

TEST_CASE("RTU: a slave that stops answering answers 203, backs off without taking the line, and is read again when it answers") {
    Line line;
    line.slaves.set_holding(1, 12, 11);
    line.slaves.set_holding(2, 12, 22);
    Machine a(line.pty.driver_end(), 1, line.buses);
    Machine b(line.pty.driver_end(), 2, line.buses);
    REQUIRE(b.read({"feed_override"})[0].ok());

    line.slaves.set_silent(2, true);
    // Two requests' worth of items: the first request times out, and every
    // item of the call answers Timeout (203) without a second wait.
    const int asked = line.slaves.requests(2);
    auto r = b.read({"feed_override", "x_position"});
    for (auto& v : r) {
        REQUIRE_FALSE(v.ok());
        CHECK(v.error().code == ErrorCode::timeout);
        CHECK_THAT(v.error().message, Catch::Contains("DEV_UNREACHABLE: modbus rtu " + line.pty.driver_end() +
                                                      " slave 2 did not answer within 300 ms"));
    }
    CHECK(line.slaves.requests(2) == asked + 1);
    CHECK(b.driver.link().state == MachineLink::disconnected);
    CHECK_THAT(b.driver.link().reason, Catch::Contains("DEV_UNREACHABLE"));

    // The other slave on the line is read meanwhile.
    CHECK(a.read({"feed_override"})[0].value() == 11);

    // Within the backoff the silent slave is not asked again (the clock
    // stands still): it does not take the shared line once per read.
    const auto transactions = b.driver.bus()->stats().transactions;
    r = b.read({"feed_override"});
    REQUIRE_FALSE(r[0].ok());
    CHECK_THAT(r[0].error().message, Catch::Contains("next attempt in"));
    CHECK(line.slaves.requests(2) == asked + 1);
    CHECK(b.driver.bus()->stats().transactions == transactions);
    // A write meanwhile is refused the same way, without a request.
    auto w = b.write("feed_override", Json(5));
    REQUIRE_FALSE(w.ok());
    CHECK(line.slaves.requests(2) == asked + 1);

    // Once due, it is asked again: still silent, 203 again, the wait doubles.
    b.now += std::chrono::milliseconds(150);
    CHECK(b.driver.link().state == MachineLink::unknown);
    r = b.read({"feed_override"});
    CHECK(r[0].error().code == ErrorCode::timeout);
    CHECK(line.slaves.requests(2) == asked + 2);

    // It answers again: the next attempt after the backoff reads it.
    line.slaves.set_silent(2, false);
    line.slaves.set_holding(2, 12, 23);
    b.now += std::chrono::milliseconds(500);
    r = b.read({"feed_override", "x_position"});
    REQUIRE(r[0].ok());
    CHECK(r[0].value() == 23);
    REQUIRE(r[1].ok());
    CHECK(b.driver.link().state == MachineLink::connected);
    REQUIRE(b.write("feed_override", Json(24)).ok());
    CHECK(line.slaves.holding(2, 12) == 24);

    // A write to a slave that went silent answers 203 too.
    line.slaves.set_silent(2, true);
    w = b.write("feed_override", Json(25));
    REQUIRE_FALSE(w.ok());
    CHECK(w.error().code == ErrorCode::timeout);
}

TEST_CASE("RTU: an answer with a bad CRC is an error for that request only, and the next request works") {
    Line line;
    line.slaves.set_holding(1, 12, 80);
    line.slaves.set_holding(1, 13, 1);
    Machine m(line.pty.driver_end(), 1, line.buses);
    REQUIRE(m.read({"feed_override"})[0].value() == 80);

    line.slaves.damage_next_answer(1);
    auto r = m.read({"feed_override", "status"});
    for (auto& v : r) {
        REQUIRE_FALSE(v.ok());
        CHECK(v.error().code == ErrorCode::unavailable);
        CHECK_THAT(v.error().message, Catch::Contains("damaged answer") && Catch::Contains("CRC"));
    }
    // Line noise is not a lost slave: no backoff, the next request is sent.
    CHECK(m.driver.link().state == MachineLink::connected);
    r = m.read({"feed_override", "status"});
    REQUIRE(r[0].ok());
    CHECK(r[0].value() == 80);
    CHECK(r[1].value() == "running");

    // A write whose answer is damaged says it may have been applied.
    line.slaves.damage_next_answer(1);
    auto w = m.write("feed_override", Json(90));
    REQUIRE_FALSE(w.ok());
    CHECK(w.error().code == ErrorCode::unavailable);
    CHECK_THAT(w.error().message, Catch::Contains("may have been applied"));
    CHECK(line.slaves.holding(1, 12) == 90);
    REQUIRE(m.write("feed_override", Json(91)).ok());
    CHECK(line.slaves.holding(1, 12) == 91);
}

TEST_CASE("RTU: a slow slave's late answer is not taken for the next slave's answer") {
    Line line;
    line.slaves.set_holding(1, 12, 11);
    line.slaves.set_holding(2, 12, 22);
    Machine a(line.pty.driver_end(), 1, line.buses);
    Machine b(line.pty.driver_end(), 2, line.buses);
    // Slave 2 answers after the driver's 300 ms: its read times out (203) ...
    line.slaves.set_delay(2, std::chrono::milliseconds(400));
    CHECK(b.read({"feed_override"})[0].error().code == ErrorCode::timeout);
    // ... and its answer reaches the line afterwards, before slave 1 is asked.
    REQUIRE(nclink::test::eventually([&] { return line.slaves.answers(2) == 1 && line.pty.waiting_at_driver_end() > 0; }));
    // Slave 1's read gets slave 1's answer, not the stale one (which would
    // be refused as another slave's, 202).
    auto r = a.read({"feed_override"});
    INFO((r[0].ok() ? std::string() : r[0].error().message));
    REQUIRE(r[0].ok());
    CHECK(r[0].value() == 11);
    CHECK(a.read({"feed_override"})[0].value() == 11);
}

TEST_CASE("RTU: an answer that stalls longer than byte_timeout_ms is cut off, a longer byte_timeout_ms waits for it") {
    Line line;
    line.slaves.set_holding(1, 12, 80);
    Machine strict(line.pty.driver_end(), 1, line.buses);  // byte_timeout_ms 50
    line.slaves.pause_next_answer(1, std::chrono::milliseconds(150));
    const int answered = line.slaves.answers(1);
    auto r = strict.read({"feed_override"});
    REQUIRE_FALSE(r[0].ok());
    CHECK(r[0].error().code == ErrorCode::timeout);
    // The rest of the cut-off answer arrives afterwards (dropped before the next request).
    REQUIRE(
        nclink::test::eventually([&] { return line.slaves.answers(1) == answered + 1 && line.pty.waiting_at_driver_end() > 0; }));

    ModbusDriver patient(std::nullopt, {}, line.buses);
    DriverContext ctx;
    ctx.config = rtu_map(line.pty.driver_end(), 1);
    ctx.config["byte_timeout_ms"] = 1000;
    REQUIRE(patient.open(ctx).ok());
    line.slaves.pause_next_answer(1, std::chrono::milliseconds(150));
    std::vector<PointRef> points{PointRef{"feed_override", DataKind::single}};
    std::vector<Result<Json>> results(1, make_error(ErrorCode::unavailable, "not read"));
    patient.read(points, results);
    INFO((results[0].ok() ? std::string() : results[0].error().message));
    REQUIRE(results[0].ok());
    CHECK(results[0].value() == 80);
    patient.close();
}

TEST_CASE("RTU: the line's turns are given in the order they were asked for") {
    Line line;
    auto bus = line.buses->attach(SerialLine{line.pty.driver_end()}).value();
    std::mutex mutex;
    std::condition_variable cv;
    bool release = false;
    std::vector<int> order;
    const SlaveSettings slave{1, std::chrono::milliseconds(100), std::chrono::milliseconds(50)};
    auto turn = [&](int who, bool hold) {
        bus->transact(slave, [&](modbus_t*) {
            std::unique_lock lock(mutex);
            order.push_back(who);
            if (hold) cv.wait(lock, [&] { return release; });
            return 0;
        });
    };
    std::thread holder(turn, 0, true);
    REQUIRE(nclink::test::eventually([&] {
        std::lock_guard lock(mutex);
        return order.size() == 1;
    }));
    // Each waiter queues while the line is held; they get it in that order.
    std::vector<std::thread> waiters;
    for (int who = 1; who <= 4; ++who) {
        waiters.emplace_back(turn, who, false);
        REQUIRE(nclink::test::eventually([&] { return bus->stats().waits == static_cast<std::uint64_t>(who); }));
    }
    {
        std::lock_guard lock(mutex);
        release = true;
    }
    cv.notify_all();
    holder.join();
    for (auto& t : waiters) t.join();
    CHECK(order == std::vector<int>{0, 1, 2, 3, 4});
}

TEST_CASE("RTU: machines naming one device with other line settings are refused at open") {
    Line line;
    Machine a(line.pty.driver_end(), 1, line.buses);
    ModbusDriver other(std::nullopt, {}, line.buses);
    DriverContext ctx;
    ctx.config = rtu_map(line.pty.driver_end(), 2);
    ctx.config["baud"] = 9600;
    auto r = other.open(ctx);
    REQUIRE_FALSE(r.ok());
    CHECK_THAT(r.error().message,
               Catch::Contains("9600 8E1 differs from the line another machine opened as") && Catch::Contains("19200 8E1"));
}

TEST_CASE("RTU: a serial device that is not there does not stop the adapter, and its items answer DEV_UNREACHABLE") {
    const std::string missing = (std::filesystem::temp_directory_path() / "nclink-no-such-tty").string();
    ModbusDriver driver;
    DriverContext ctx;
    ctx.config = rtu_map(missing, 1);
    REQUIRE(driver.open(ctx).ok());
    CHECK(driver.link().state == MachineLink::disconnected);
    std::vector<PointRef> points{PointRef{"feed_override", DataKind::single}};
    std::vector<Result<Json>> results(1, make_error(ErrorCode::unavailable, "not read"));
    driver.read(points, results);
    REQUIRE_FALSE(results[0].ok());
    CHECK(results[0].error().code == ErrorCode::unavailable);
    CHECK_THAT(results[0].error().message, Catch::Contains("DEV_UNREACHABLE") && Catch::Contains("cannot open"));
}

TEST_CASE("RTU: the plugin's drivers share a device two machines name") {
    Line line;
    line.slaves.set_holding(1, 12, 11);
    line.slaves.set_holding(2, 12, 22);
    const std::string plugin = std::string(NCLINK_BINARY_DIR) + "/lib/nclink-modbus.so";
    auto a = load_driver_plugin(plugin, rtu_map(line.pty.driver_end(), 1));
    auto b = load_driver_plugin(plugin, rtu_map(line.pty.driver_end(), 2));
    // A plugin's driver is made and opened by the loader.
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    auto read = [](Driver& d) {
        std::vector<PointRef> points{PointRef{"feed_override", DataKind::single}};
        std::vector<Result<Json>> results(1, make_error(ErrorCode::unavailable, "not read"));
        d.read(points, results);
        return results[0];
    };
    CHECK(read(*a.value()).value() == 11);
    CHECK(read(*b.value()).value() == 22);

    // They found one bus: a third machine on that device at another speed
    // is refused, which only a shared line can know.
    Json slower = rtu_map(line.pty.driver_end(), 3);
    slower["baud"] = 9600;
    auto c = load_driver_plugin(plugin, slower);
    REQUIRE_FALSE(c.ok());
    CHECK_THAT(c.error().message, Catch::Contains("differs from the line another machine opened"));
}
