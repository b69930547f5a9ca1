// The driver's configuration, and an agent that is absent, broken or answers
// HTTP errors: open() fails with a clear error naming it, never a crash.
#include "mtconnect/agent_source.hpp"
#include "mtconnect/mtconnect_driver.hpp"

#include <nclink/driver_plugin_loader.hpp>

#include "support/wait.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <algorithm>
#include <mutex>
#include <thread>

using namespace nclink;
using namespace nclink::mtconnect;

namespace {

/// A local HTTP server answering /probe with what the test says.
struct FakeAgent {
    explicit FakeAgent(std::function<void(const httplib::Request&, httplib::Response&)> probe,
                       const std::function<void(httplib::Server&)>& more = {}) {
        server.Get("/probe", std::move(probe));
        if (more) more(server);  // every route before the server runs
        port = server.bind_to_any_port("127.0.0.1");
        thread = std::thread([this] { server.listen_after_bind(); });
        // stop() before the listen loop runs would be lost (and join() hang).
        while (!server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ~FakeAgent() {
        server.stop();
        thread.join();
    }
    std::string url() const { return "http://127.0.0.1:" + std::to_string(port); }
    httplib::Server server;
    int port = 0;
    std::thread thread;
};

Error open_error(const Json& config) {
    MtConnectDriver driver;
    auto r = driver.open(DriverContext{config, Logger{}});
    REQUIRE_FALSE(r.ok());
    return r.error();
}

}  // namespace

TEST_CASE("driver configuration: one source, known keys, sane numbers") {
    auto ok = parse_driver_config(Json{{"agent", "http://127.0.0.1:5000"}, {"interval_ms", 200}, {"count", 50}});
    REQUIRE(ok.ok());
    CHECK(ok->interval == std::chrono::milliseconds(200));
    CHECK(ok->count == 50);
    CHECK(parse_driver_config(Json{{"shdr", "127.0.0.1:7878"}, {"probe_file", "d.xml"}}).ok());
    CHECK(parse_driver_config(nullptr).error().code == ErrorCode::parameter_missing);
    CHECK(parse_driver_config(Json::object()).error().code == ErrorCode::parameter_missing);
    CHECK(parse_driver_config(Json{{"agent", "http://a"}, {"shdr", "b:1"}}).error().code == ErrorCode::parameter_missing);
    CHECK(parse_driver_config(Json{{"shdr", "b:1"}}).error().message.find("probe_file") != std::string::npos);
    CHECK(parse_driver_config(Json{{"agent", "http://a"}, {"intervall_ms", 5}}).error().code == ErrorCode::keys_of_arguments);
    CHECK(parse_driver_config(Json{{"agent", "http://a"}, {"interval_ms", "fast"}}).error().code == ErrorCode::value_type);
    CHECK(parse_driver_config(Json{{"agent", "http://a"}, {"count", 0}}).error().code == ErrorCode::value_type);
    CHECK(parse_driver_config(Json{{"agent", 5}}).error().code == ErrorCode::value_type);
}

TEST_CASE("agent URLs") {
    auto u = parse_agent_url("http://10.0.0.7:5000/agent/");
    REQUIRE(u.ok());
    CHECK(u->host == "10.0.0.7");
    CHECK(u->port == 5000);
    CHECK(u->prefix == "/agent");
    CHECK(parse_agent_url("http://agent").value().port == 80);
    CHECK(parse_agent_url("http://[::1]:5000").value().host == "::1");
    CHECK_FALSE(parse_agent_url("https://agent").ok());
    CHECK_FALSE(parse_agent_url("http://agent:99999").ok());
    CHECK_FALSE(parse_agent_url("http://:5000").ok());
}

TEST_CASE("an absent, failing or broken agent fails open() with a clear error") {
    SECTION("nothing listens") {
        int port = 0;
        {
            FakeAgent gone([](const httplib::Request&, httplib::Response&) {});
            port = gone.port;
        }
        const Error e = open_error(Json{{"agent", "http://127.0.0.1:" + std::to_string(port)}, {"timeout_ms", 500}});
        CHECK(e.code == ErrorCode::unavailable);
        CHECK(e.message.find("GET http://127.0.0.1:" + std::to_string(port) + "/probe") != std::string::npos);
    }
    SECTION("HTTP 500") {
        FakeAgent agent([](const httplib::Request&, httplib::Response& res) {
            res.status = 500;
            res.set_content("boom", "text/plain");
        });
        const Error e = open_error(Json{{"agent", agent.url()}});
        CHECK(e.message.find("HTTP 500") != std::string::npos);
    }
    SECTION("not XML") {
        FakeAgent agent(
            [](const httplib::Request&, httplib::Response& res) { res.set_content("{\"json\": 1}", "application/json"); });
        const Error e = open_error(Json{{"agent", agent.url()}});
        CHECK(e.code == ErrorCode::syntax_error);
        CHECK(e.message.find("not well-formed") != std::string::npos);
    }
    SECTION("an Error document") {
        FakeAgent agent([](const httplib::Request&, httplib::Response& res) {
            res.status = 404;
            res.set_content("<MTConnectError><Errors><Error errorCode=\"NO_DEVICE\">none</Error></Errors></MTConnectError>",
                            "text/xml");
        });
        const Error e = open_error(Json{{"agent", agent.url()}});
        CHECK(e.message.find("NO_DEVICE: none") != std::string::npos);
    }
    SECTION("a device the probe does not have") {
        FakeAgent agent([](const httplib::Request&, httplib::Response& res) {
            res.set_content(
                "<MTConnectDevices><Header instanceId='1'/><Devices><Device id='d' name='m' uuid='u'/></Devices>"
                "</MTConnectDevices>",
                "text/xml");
        });
        const Error e = open_error(Json{{"agent", agent.url()}, {"device", "lathe"}});
        CHECK(e.code == ErrorCode::node_not_exists);
    }
    SECTION("an SHDR probe file that is not there") {
        const Error e = open_error(Json{{"shdr", "127.0.0.1:1"}, {"probe_file", "/nonexistent/devices.xml"}});
        CHECK(e.message.find("/nonexistent/devices.xml") != std::string::npos);
    }
}

TEST_CASE("writes are refused with 301: MTConnect is read-only") {
    MtConnectDriver driver;
    WriteRequest w;
    w.id = "x_position";
    auto r = driver.write(w);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::permission_denied);
    CHECK(r.error().message.find("read-only") != std::string::npos);
}

TEST_CASE("nclink-mtconnect.so loads through the plugin ABI, answers from the agent and refuses Sets") {
    const std::string streams = R"(<MTConnectStreams><Header instanceId="7" nextSequence="3" firstSequence="1" lastSequence="2"/>
<Streams><DeviceStream name="m" uuid="u"><ComponentStream component="Device" componentId="d"><Events>
<Availability dataItemId="avail" sequence="1">AVAILABLE</Availability><Program dataItemId="prog" sequence="2">O1234</Program>
</Events></ComponentStream></DeviceStream></Streams></MTConnectStreams>)";
    FakeAgent agent(
        [](const httplib::Request&, httplib::Response& res) {
            res.set_content(R"(<MTConnectDevices><Header instanceId="7"/><Devices><Device id="d" name="m" uuid="u">
<DataItems><DataItem category="EVENT" id="avail" type="AVAILABILITY"/>
<DataItem category="EVENT" id="prog" type="PROGRAM"/></DataItems></Device></Devices></MTConnectDevices>)",
                            "text/xml");
        },
        [&](httplib::Server& server) {
            server.Get("/current", [&](const httplib::Request&, httplib::Response& res) { res.set_content(streams, "text/xml"); });
            server.Get("/sample", [&](const httplib::Request&, httplib::Response& res) {
                res.set_content(
                    R"(<MTConnectStreams><Header instanceId="7" nextSequence="3" firstSequence="1" lastSequence="2"/><Streams/></MTConnectStreams>)",
                    "text/xml");
            });
        });
    const std::string path = std::string(NCLINK_BINARY_DIR) + "/lib/nclink-mtconnect.so";
    auto loaded = load_driver_plugin(path, Json{{"agent", agent.url()}, {"interval_ms", 50}});
    REQUIRE(loaded.ok());
    std::shared_ptr<Driver> driver = loaded.value();
    CHECK(driver->info().name == "mtconnect");
    std::vector<PointRef> points{PointRef{"prog", DataKind::single, no_handle}};
    std::vector<Result<Json>> results(1, make_error(ErrorCode::unavailable));
    CHECK(nclink::test::eventually([&] {
        driver->read(points, results);
        return results[0].ok() && results[0].value() == Json("O1234");
    }));
    CHECK(driver->link().state == MachineLink::connected);
    WriteRequest w;
    w.id = "prog";
    auto written = driver->write(w);
    REQUIRE_FALSE(written.ok());
    CHECK(written.error().code == ErrorCode::permission_denied);
    driver->close();

    auto refused = load_driver_plugin(path, Json{{"agent", "ftp://x"}});
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().message.find("only http://") != std::string::npos);
}

namespace {

std::string probe_of(const std::string& instance, const std::string& extra_item) {
    return R"(<MTConnectDevices><Header instanceId=")" + instance +
           R"("/><Devices><Device id="d" name="m" uuid="u"><DataItems>
<DataItem category="EVENT" id="prog" type="PROGRAM"/>)" +
           extra_item + "</DataItems></Device></Devices></MTConnectDevices>";
}

std::string streams_of(const std::string& instance, int next, const std::string& events) {
    return R"(<MTConnectStreams><Header instanceId=")" + instance + R"(" nextSequence=")" + std::to_string(next) +
           R"(" firstSequence="1" lastSequence=")" + std::to_string(next - 1) +
           R"("/><Streams><DeviceStream name="m" uuid="u"><ComponentStream component="Device" componentId="d"><Events>)" +
           events + "</Events></ComponentStream></DeviceStream></Streams></MTConnectStreams>";
}

}  // namespace

TEST_CASE("an agent that restarts between two polls (new instanceId) is probed and read again, OUT_OF_RANGE reads /current") {
    // A scripted agent: instance 7 until `restarted`, then instance 8 with
    // one DataItem more; its /sample answers OUT_OF_RANGE once when asked.
    std::mutex m;
    bool restarted = false, out_of_range_once = false;
    std::vector<std::string> requests;
    FakeAgent agent(
        [&](const httplib::Request&, httplib::Response& res) {
            std::lock_guard lock(m);
            requests.push_back("probe");
            res.set_content(
                restarted ? probe_of("8", R"(<DataItem category="EVENT" id="tool" type="TOOL_NUMBER"/>)") : probe_of("7", ""),
                "text/xml");
        },
        [&](httplib::Server& server) {
            server.Get("/current", [&](const httplib::Request&, httplib::Response& res) {
                std::lock_guard lock(m);
                requests.push_back("current");
                res.set_content(restarted ? streams_of("8", 3,
                                                       R"(<Program dataItemId="prog" sequence="1">O8</Program>)"
                                                       R"(<ToolNumber dataItemId="tool" sequence="2">12</ToolNumber>)")
                                          : streams_of("7", 2, R"(<Program dataItemId="prog" sequence="1">O7</Program>)"),
                                "text/xml");
            });
            server.Get("/sample", [&](const httplib::Request& req, httplib::Response& res) {
                std::lock_guard lock(m);
                requests.push_back("sample " + req.get_param_value("from"));
                if (out_of_range_once) {
                    out_of_range_once = false;
                    res.status = 404;
                    res.set_content(
                        R"(<MTConnectError><Errors><Error errorCode="OUT_OF_RANGE">'from' is too small</Error></Errors></MTConnectError>)",
                        "text/xml");
                    return;
                }
                res.set_content(restarted ? streams_of("8", 3, "") : streams_of("7", 2, ""), "text/xml");
            });
        });
    mtconnect::MtConnectDriver driver;
    REQUIRE(driver.open(DriverContext{Json{{"agent", agent.url()}, {"interval_ms", 20}}, Logger{}}).ok());
    auto read = [&](const std::string& id) {
        std::vector<PointRef> points{PointRef{id, DataKind::single, no_handle}};
        std::vector<Result<Json>> results(1, make_error(ErrorCode::unavailable));
        driver.read(points, results);
        return results[0].ok() ? results[0].value() : Json(nullptr);
    };
    CHECK(nclink::test::eventually([&] { return read("prog") == Json("O7"); }));
    CHECK(nclink::test::eventually([&] { return driver.stats().samples >= 2; }));
    {
        std::lock_guard lock(m);
        CHECK(std::find(requests.begin(), requests.end(), "sample 2") != requests.end());  // from = nextSequence
        out_of_range_once = true;
    }
    CHECK(nclink::test::eventually([&] { return driver.stats().out_of_range == 1 && driver.stats().currents >= 2; }));
    CHECK(read("tool").is_null());  // not in instance 7's probe
    {
        std::lock_guard lock(m);
        restarted = true;
    }
    CHECK(nclink::test::eventually([&] { return read("prog") == Json("O8"); }));
    CHECK(read("tool") == Json(12));  // the new probe's item, read from the new /current
    const auto stats = driver.stats();
    CHECK(stats.restarts == 1);
    CHECK(stats.probes == 2);
    CHECK(stats.failures == 0);  // no request failed: the restart was seen by its instanceId alone
    CHECK(driver.link().state == MachineLink::connected);
    driver.close();
}
