// The SHDR source against an adapter written here from the protocol's
// description (MTConnect 1.4 part 1, the adapter's line format): data lines
// of several key|value pairs, a condition, a MESSAGE, another device's line,
// an unknown key, "* PING" answered "* PONG <ms>", a dropped connection and
// an adapter that falls silent past its heartbeat.
#include "mtconnect/mtconnect_driver.hpp"

#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;

namespace {

const char* const kDevices = R"(<?xml version="1.0" encoding="UTF-8"?>
<MTConnectDevices xmlns="urn:mtconnect.org:MTConnectDevices:1.4">
  <Header creationTime="2024-01-01T00:00:00Z" sender="test" instanceId="1" version="1.4.0" bufferSize="16"/>
  <Devices>
    <Device id="d1" name="VMC" uuid="vmc-1">
      <DataItems>
        <DataItem category="EVENT" id="avail" type="AVAILABILITY"/>
        <DataItem category="EVENT" id="msg" type="MESSAGE"/>
      </DataItems>
      <Components>
        <Axes id="axes"><Components>
          <Linear id="X" name="X"><DataItems>
            <DataItem category="SAMPLE" id="Xact" type="POSITION" subType="ACTUAL" units="MILLIMETER"/>
          </DataItems></Linear>
          <Rotary id="C" name="C"><DataItems>
            <DataItem category="SAMPLE" id="Srpm" type="ROTARY_VELOCITY" subType="ACTUAL" units="REVOLUTION/MINUTE"><Source>spindle_speed</Source></DataItem>
          </DataItems></Rotary>
        </Components></Axes>
        <Controller id="cont" name="controller"><DataItems>
          <DataItem category="CONDITION" id="system" type="SYSTEM"/>
          <DataItem category="EVENT" id="execution" type="EXECUTION"/>
        </DataItems></Controller>
      </Components>
    </Device>
  </Devices>
</MTConnectDevices>)";

/// The adapter side: a listening socket on loopback and one connection at a time.
struct ShdrPeer {
    ShdrPeer() {
        listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::bind(listener, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
        REQUIRE(::listen(listener, 4) == 0);
        socklen_t len = sizeof a;
        ::getsockname(listener, reinterpret_cast<sockaddr*>(&a), &len);
        port = ntohs(a.sin_port);
    }
    ~ShdrPeer() {
        drop();
        ::close(listener);
    }
    bool accept_one(std::chrono::milliseconds within = 10s) {
        pollfd p{listener, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(within.count())) != 1) return false;
        conn = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
        pending.clear();
        return conn >= 0;
    }
    void send(const std::string& text) const {
        REQUIRE(::send(conn, text.data(), text.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(text.size()));
    }
    /// The next line the reader sent, "" when none came within `within`.
    std::string line(std::chrono::milliseconds within = 5s) {
        const auto end = std::chrono::steady_clock::now() + within;
        for (;;) {
            if (const auto nl = pending.find('\n'); nl != std::string::npos) {
                std::string l = pending.substr(0, nl);
                pending.erase(0, nl + 1);
                return l;
            }
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
            if (left.count() <= 0) return {};
            pollfd p{conn, POLLIN, 0};
            if (::poll(&p, 1, static_cast<int>(left.count())) != 1) return {};
            char buf[512];
            const ssize_t n = ::recv(conn, buf, sizeof buf, 0);
            if (n <= 0) return {};
            pending.append(buf, static_cast<std::size_t>(n));
        }
    }
    /// True when the reader closed its end (recv gives 0) within `within`.
    bool closed_by_peer(std::chrono::milliseconds within) {
        const auto end = std::chrono::steady_clock::now() + within;
        while (std::chrono::steady_clock::now() < end) {
            pollfd p{conn, POLLIN, 0};
            if (::poll(&p, 1, 100) == 1) {
                char buf[512];
                const ssize_t n = ::recv(conn, buf, sizeof buf, 0);
                if (n <= 0) return true;  // PINGs are read and dropped: this adapter stays silent
            }
        }
        return false;
    }
    void drop() {
        if (conn >= 0) ::close(conn);
        conn = -1;
    }
    int listener = -1;
    int conn = -1;
    int port = 0;
    std::string pending;
};

Json read_one(mtconnect::MtConnectDriver& d, const std::string& id) {
    std::vector<PointRef> points{PointRef{id, DataKind::single, no_handle}};
    std::vector<Result<Json>> results(1, make_error(ErrorCode::unavailable));
    if (d.link().state == MachineLink::disconnected) return nullptr;  // what the SDK does (driver.hpp)
    d.read(points, results);
    return results[0].ok() ? results[0].value() : Json(nullptr);
}

}  // namespace

TEST_CASE("SHDR source: values, a condition, PING/PONG, a dropped connection and a silent adapter") {
    nclink::test::ScratchDir scratch("nclink-shdr-itest-");
    std::filesystem::create_directories(scratch.path);
    const auto devices = scratch.path / "devices.xml";
    std::ofstream(devices) << kDevices;
    ShdrPeer adapter;
    mtconnect::MtConnectDriver driver;
    REQUIRE(driver
                .open(DriverContext{Json{{"shdr", "127.0.0.1:" + std::to_string(adapter.port)},
                                         {"probe_file", devices.string()},
                                         {"retry_ms", 100},
                                         {"ping_ms", 200}},
                                    Logger{}})
                .ok());

    REQUIRE(adapter.accept_one());
    CHECK(adapter.line() == "* PING");  // the reader asks for the heartbeat first
    adapter.send("* PONG 2000\n");
    adapter.send("2024-01-01T00:00:00.000Z|avail|AVAILABLE|Xact|12.5|execution|ACTIVE\n");
    adapter.send("2024-01-01T00:00:00.001Z|VMC:system|fault|1001|HIGH||Spindle overload\n");
    adapter.send("2024-01-01T00:00:00.002Z|spindle_speed|1200\n");
    adapter.send("2024-01-01T00:00:00.003Z|msg|E1|Door open\n");
    adapter.send("2024-01-01T00:00:00.004Z|other-device:Xact|99|unknown_key|1\n");
    CHECK(eventually([&] { return read_one(driver, "msg") == Json("Door open"); }));
    CHECK(read_one(driver, "Xact") == Json(12.5));
    CHECK(read_one(driver, "Srpm") == Json(1200.0));
    CHECK(read_one(driver, "execution").is_string());
    CHECK(read_one(driver, "system") == Json::array({Json{{"number", 1001}, {"text", "Spindle overload"}, {"level", "FAULT"}}}));
    CHECK(driver.link().state == MachineLink::connected);
    CHECK(eventually([&] { return driver.stats().pongs >= 1; }));

    adapter.send("2024-01-01T00:00:00.005Z|system|normal||||\n");
    adapter.send("2024-01-01T00:00:00.006Z|Xact|UNAVAILABLE\n");
    CHECK(eventually([&] { return read_one(driver, "system") == Json::array(); }));
    CHECK(eventually([&] { return read_one(driver, "Xact").is_null(); }));  // UNAVAILABLE: no value (202)

    // The adapter drops the connection: everything is unknown, the link is down.
    adapter.drop();
    CHECK(eventually([&] { return driver.link().state == MachineLink::disconnected; }));
    CHECK(read_one(driver, "msg").is_null());
    // ... and the reader comes back; the adapter sends its state again.
    REQUIRE(adapter.accept_one());
    adapter.send("2024-01-01T00:00:01.000Z|avail|AVAILABLE|Xact|3\n");
    CHECK(eventually([&] { return read_one(driver, "Xact") == Json(3.0); }));
    CHECK(eventually([&] { return driver.stats().connects == 2; }));

    // An adapter that announced a 300 ms heartbeat and then falls silent
    // (no data, no PONG) is taken as gone: the reader closes and reconnects.
    CHECK(adapter.line() == "* PING");
    adapter.send("* PONG 300\n");
    CHECK(adapter.closed_by_peer(10s));
    CHECK(eventually([&] { return driver.link().state == MachineLink::disconnected; }));
    adapter.drop();
    REQUIRE(adapter.accept_one());
    CHECK(eventually([&] { return driver.stats().connects == 3; }));
    driver.close();
}
