// nclink-bridge end to end: mosquitto, the simulated mill's adapter, the
// bridge in-process, and real consumers — an HTTP client, xmllint with the
// MTConnect 1.4 schemas, an NC-Link client that checks what the bridge says,
// and a plain TCP reader for SHDR.
#include "bridge/bridge.hpp"

#include "integration/bridge/bridge_itest.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::attribute;
using nclink::test::encoded;
using nclink::test::eventually;
using nclink::test::validates;

namespace {

const std::string kDev = nclink::test::kSimMillDevice;

struct Rig : nclink::test::SimMillRig {
    Rig() {
        start();
        bridge::BridgeConfig c;
        c.broker_url = broker.url();
        c.http_port = 0;
        c.shdr_port = 0;
        c.buffer_size = 4096;
        c.max_request_bytes = 4096;
        c.poll_interval = 200ms;
        c.heartbeat = 500ms;
        c.ex_cid = "bridge-itest";
        the_bridge = std::make_unique<bridge::Bridge>(c, Logger{});
        REQUIRE(the_bridge->start().ok());
        http = std::make_unique<httplib::Client>("127.0.0.1", the_bridge->http_port());
        http->set_read_timeout(10, 0);
        client = make_client("checker");
        REQUIRE(eventually([&] {
            auto r = http->Get("/current");
            return r && r->status == 200 && r->body.find(">AVAILABLE</Availability>") != std::string::npos;
        }, 20s));
    }
    ~Rig() override {
        the_bridge.reset();  // before the adapter and the broker
    }
    httplib::Result get(const std::string& path) { return http->Get(path.c_str()); }
    void expect_error(const std::string& path, int status, const std::string& code) {
        INFO(path);
        auto r = get(path);
        REQUIRE(r);
        CHECK(r->status == status);
        CHECK(r->body.find("errorCode=\"" + code + "\"") != std::string::npos);
        CHECK(validates(r->body, "Error"));
    }

    std::unique_ptr<bridge::Bridge> the_bridge;
    std::unique_ptr<httplib::Client> http;
};

}  // namespace

TEST_CASE("bridge serves valid MTConnect documents that agree with NC-Link Query") {
    Rig rig;
    auto probe = rig.get("/probe");
    REQUIRE(probe);
    CHECK(probe->status == 200);
    CHECK(probe->body.find("uuid=\"" + kDev + "\"") != std::string::npos);
    CHECK(validates(probe->body, "Devices"));
    CHECK(validates(rig.get("/" + kDev + "/probe")->body, "Devices"));

    // A value nobody changes: the bridge's current equals a Query of the same item.
    const Json override_value = rig.query_one("spindle_override");
    REQUIRE(override_value.is_number());
    std::string shown;
    REQUIRE(eventually([&] {
        auto current = rig.get("/current?path=" + encoded("//DataItem[@id=\"" + kDev + ".spindle_override\"]"));
        std::smatch m;
        if (!current || !std::regex_search(current->body, m, std::regex("dataItemId=\"" + kDev + "\\.spindle_override\"[^>]*>([^<]*)<")))
            return false;
        shown = m[1];
        return shown != "UNAVAILABLE" && std::stod(shown) == override_value.get<double>();
    }));
    auto current = rig.get("/current");
    REQUIRE(current);
    CHECK(current->status == 200);
    CHECK(validates(current->body, "Streams"));
    for (const char* attr : {"creationTime", "sender", "instanceId", "version", "bufferSize", "nextSequence",
                             "firstSequence", "lastSequence"})
        CHECK_FALSE(attribute(current->body, attr).empty());
    auto positions = rig.get("/current?path=" + encoded("//DataItem[@type=\"POSITION\"]"));
    REQUIRE(positions);
    CHECK(positions->body.find("<Position") != std::string::npos);
    CHECK(positions->body.find("<Execution") == std::string::npos);
    CHECK(validates(rig.get("/current?path=//Axes")->body, "Streams"));

    // /sample: consecutive calls chain through nextSequence with no gap.
    std::uint64_t from = std::stoull(attribute(current->body, "firstSequence"));
    std::uint64_t expected = from;
    for (int call = 0; call < 5; ++call) {
        auto sample = rig.get("/sample?from=" + std::to_string(from) + "&count=200");
        REQUIRE(sample);
        REQUIRE(sample->status == 200);
        if (call == 0) CHECK(validates(sample->body, "Streams"));
        std::regex seq(" sequence=\"([0-9]+)\"");
        std::vector<std::uint64_t> seen;
        for (auto it = std::sregex_iterator(sample->body.begin(), sample->body.end(), seq); it != std::sregex_iterator(); ++it)
            seen.push_back(std::stoull((*it)[1]));
        std::sort(seen.begin(), seen.end());
        seen.erase(std::unique(seen.begin(), seen.end()), seen.end());  // a condition may give several elements
        for (auto s : seen) CHECK(s == expected++);
        from = std::stoull(attribute(sample->body, "nextSequence"));
        CHECK(from == expected);
    }

    // Bad input: the right error document each, and the bridge stays up.
    rig.expect_error("/no/such/thing/here", 404, "INVALID_URI");
    rig.expect_error("/sample?from=abc", 400, "INVALID_REQUEST");
    rig.expect_error("/sample?from=0", 400, "OUT_OF_RANGE");
    rig.expect_error("/sample?count=99999999", 400, "OUT_OF_RANGE");
    rig.expect_error("/sample?from=99999999999", 400, "OUT_OF_RANGE");
    rig.expect_error("/current?at=0", 400, "OUT_OF_RANGE");
    rig.expect_error("/current?at=x", 400, "INVALID_REQUEST");
    rig.expect_error("/current?path=" + encoded("//DataItem["), 400, "INVALID_PATH");
    rig.expect_error("/nosuchmachine/current", 404, "NO_DEVICE");
    rig.expect_error("/assets", 400, "UNSUPPORTED");
    auto too_big = rig.http->Post("/gbt18759/write", std::string(10000, 'x'), "application/xml");
    REQUIRE(too_big);
    CHECK(too_big->status == 413);
    CHECK(validates(too_big->body, "Error"));
    auto wrong_method = rig.http->Post("/current", "x", "text/plain");
    REQUIRE(wrong_method);
    CHECK(wrong_method->status == 405);
    auto not_setable = rig.http->Post(
        "/gbt18759/write",
        "<DataWriteRequest><Operation command=\"SET\"><Value dataItemId=\"x_position\">1</Value></Operation></DataWriteRequest>",
        "application/xml");
    REQUIRE(not_setable);
    CHECK(not_setable->status == 400);
    CHECK(not_setable->body.find("not setable") != std::string::npos);
    CHECK(validates(not_setable->body, "Error"));
    auto after = rig.get("/current");
    REQUIRE(after);
    CHECK(after->status == 200);

    // GB/T 18759.6: the same documents under its prefix, and data write as NC-Link Set.
    CHECK(validates(rig.get("/gbt18759/probe")->body, "Devices"));
    CHECK(validates(rig.get("/gbt18759/current")->body, "Streams"));
    CHECK(validates(rig.get("/gbt18759/enquire?From=" + std::to_string(from) + "&Count=5")->body, "Streams"));
    auto write = rig.http->Post(
        "/gbt18759/write",
        "<DataWriteRequest><Header version=\"1.0\" sender=\"itest\"/><Operation command=\"SET\">"
        "<Value dataItemId=\"spindle_override\">87</Value></Operation></DataWriteRequest>",
        "application/xml");
    REQUIRE(write);
    CHECK(write->status == 200);
    CHECK(rig.query_one("spindle_override") == 87);
    auto write_by_mt_id = rig.http->Post(
        "/gbt18759/write",
        "<DataWriteRequest><Operation command=\"SET\"><Value dataItemId=\"" + kDev +
            ".spindle_override\">88</Value></Operation></DataWriteRequest>",
        "application/xml");
    REQUIRE(write_by_mt_id);
    CHECK(write_by_mt_id->status == 200);
    CHECK(rig.query_one("spindle_override") == 88);

    // The JSON API: devices, model, nodeset, set.
    auto devices = rig.get("/nclink/v1/devices");
    REQUIRE(devices);
    const Json list = Json::parse(devices->body);
    REQUIRE(list["devices"].size() == 1);
    CHECK(list["devices"][0]["dev"] == kDev);
    CHECK(list["devices"][0]["state"] == "online");
    auto model = rig.get("/nclink/v1/devices/" + kDev + "/model");
    REQUIRE(model);
    CHECK(Json::parse(model->body).contains("devices"));
    auto nodeset = rig.get("/nclink/v1/devices/" + kDev + "/nodeset.xml?profile=basic");
    REQUIRE(nodeset);
    CHECK(nodeset->status == 200);
    CHECK(nodeset->body.find("urn:nclink:device:" + kDev) != std::string::npos);
    auto set = rig.http->Post(("/nclink/v1/devices/" + kDev + "/set").c_str(), R"({"id":"spindle_override","value":93})",
                              "application/json");
    REQUIRE(set);
    CHECK(Json::parse(set->body) == Json{{"code", "OK"}});
    CHECK(rig.query_one("spindle_override") == 93);
    auto refused = rig.http->Post(("/nclink/v1/devices/" + kDev + "/set").c_str(), R"({"id":"x_position","value":1})",
                                  "application/json");
    REQUIRE(refused);
    CHECK(refused->status == 200);
    CHECK(Json::parse(refused->body)["code"] == "NG");
    auto malformed = rig.http->Post(("/nclink/v1/devices/" + kDev + "/set").c_str(), "{", "application/json");
    REQUIRE(malformed);
    CHECK(malformed->status == 400);
    auto unknown = rig.http->Post("/nclink/v1/devices/nobody/set", R"({"id":"a","value":1})", "application/json");
    REQUIRE(unknown);
    CHECK(unknown->status == 404);

    // The SSE stream: a snapshot first, then live values.
    httplib::Client sse("127.0.0.1", rig.the_bridge->http_port());
    sse.set_read_timeout(10, 0);
    std::string received;
    auto res = sse.Get(("/nclink/v1/stream?dev=" + kDev).c_str(), [&](const char* data, size_t length) {
        received.append(data, length);
        return received.find("event: value") == std::string::npos;  // stop after the first live value
    });
    CHECK(received.rfind("event: snapshot\ndata: ", 0) == 0);
    const auto first_line_end = received.find('\n', 16);
    const Json snapshot = Json::parse(received.substr(std::string("event: snapshot\ndata: ").size(),
                                                      first_line_end - std::string("event: snapshot\ndata: ").size()));
    CHECK(snapshot["dev"] == kDev);
    CHECK(snapshot["state"] == "online");
    CHECK_FALSE(snapshot["values"].empty());
    CHECK(received.find("event: value\ndata: {") != std::string::npos);
}

TEST_CASE("bridge turns a stopped adapter UNAVAILABLE and brings its values back") {
    Rig rig;
    rig.adapter->stop();
    rig.adapter.reset();
    REQUIRE(eventually([&] {
        auto r = rig.get("/current");
        return r && r->body.find(">UNAVAILABLE</Availability>") != std::string::npos;
    }));
    auto current = rig.get("/current?path=" + encoded("//DataItem[@type=\"POSITION\"]"));
    REQUIRE(current);
    CHECK(current->body.find(">UNAVAILABLE</Position>") != std::string::npos);
    CHECK(validates(current->body, "Streams"));
    auto devices = Json::parse(rig.get("/nclink/v1/devices")->body);
    CHECK(devices["devices"][0]["state"] == "offline");

    rig.driver = nullptr;  // a fresh simulated mill, as after a real restart
    rig.start();
    REQUIRE(eventually([&] {
        auto r = rig.get("/current?path=" + encoded("//DataItem[@id=\"" + kDev + ".x_position\"]"));
        return r && r->body.find(">AVAILABLE</Availability>") == std::string::npos &&
               r->body.find("<Position") != std::string::npos && r->body.find(">UNAVAILABLE</Position>") == std::string::npos;
    }, 20s));
}

namespace {
int connect_to(int port) {
    int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    return fd;
}
// Reads lines until `done` says so or 10 s pass.
std::string read_until(int fd, const std::function<bool(const std::string&)>& done) {
    std::string text;
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (!done(text) && std::chrono::steady_clock::now() < deadline) {
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, 100) <= 0) continue;
        char buffer[4096];
        const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
        if (n <= 0) break;
        text.append(buffer, static_cast<std::size_t>(n));
    }
    return text;
}
}  // namespace

TEST_CASE("bridge speaks SHDR: snapshot, line format, PING PONG, reconnect") {
    Rig rig;
    for (int round = 0; round < 2; ++round) {  // the second round is a reconnect
        int fd = connect_to(rig.the_bridge->shdr_port());
        const std::string snapshot = read_until(fd, [](const std::string& t) { return t.find("_avail|AVAILABLE\n") != std::string::npos; });
        CHECK(snapshot.find("_avail|AVAILABLE\n") != std::string::npos);
        const std::regex line_format(R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z\|[^|\n]+:[^|\n]+\|[^\n]*$)");
        std::istringstream lines(snapshot);
        std::string line;
        int checked = 0;
        while (std::getline(lines, line))
            if (!line.empty() && checked++ < 200) {
                INFO(line);
                CHECK(std::regex_match(line, line_format));
            }
        CHECK(checked > 5);
        const std::string ping = "* PING\n";
        REQUIRE(::send(fd, ping.data(), ping.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(ping.size()));
        const std::string after = read_until(fd, [](const std::string& t) { return t.find("* PONG ") != std::string::npos; });
        CHECK(after.find("* PONG 500\n") != std::string::npos);
        // Live changes keep coming (the 1 ms channel moves the axes).
        const std::string live = read_until(fd, [](const std::string& t) { return t.find(":" + kDev + ".x_position|") != std::string::npos; });
        CHECK(live.find(":" + kDev + ".x_position|") != std::string::npos);
        ::close(fd);
    }
}
