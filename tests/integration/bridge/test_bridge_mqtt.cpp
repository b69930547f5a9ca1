// nclink-bridge end to end: mosquitto, the simulated mill's adapter, the
// bridge in-process, and real consumers — an HTTP client, xmllint with the
// MTConnect 1.4 schemas, an NC-Link client that checks what the bridge says,
// and a plain TCP reader for SHDR.
#include "bridge/bridge.hpp"

#include "integration/bridge/bridge_itest.hpp"
#include "support/ack_dropping_proxy.hpp"
#include "support/mosquitto_broker.hpp"
#include "support/rig.hpp"
#include "support/shdr_agent.hpp"
#include "support/sim_mill_rig.hpp"
#include "support/wait.hpp"

#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

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
#include <sstream>
#include <thread>
#include <atomic>
#include <mutex>
#include <algorithm>

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
        REQUIRE(eventually(
            [&] {
                auto r = http->Get("/current");
                return r && r->status == 200 && r->body.find(">AVAILABLE</Availability>") != std::string::npos;
            },
            20s));
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
        if (!current ||
            !std::regex_search(current->body, m, std::regex("dataItemId=\"" + kDev + "\\.spindle_override\"[^>]*>([^<]*)<")))
            return false;
        shown = m[1];
        return shown != "UNAVAILABLE" && std::stod(shown) == override_value.get<double>();
    }));
    auto current = rig.get("/current");
    REQUIRE(current);
    CHECK(current->status == 200);
    CHECK(validates(current->body, "Streams"));
    for (const char* attr :
         {"creationTime", "sender", "instanceId", "version", "bufferSize", "nextSequence", "firstSequence", "lastSequence"})
        CHECK_FALSE(attribute(current->body, attr).empty());
    auto positions = rig.get("/current?path=" + encoded("//DataItem[@type=\"POSITION\"]"));
    REQUIRE(positions);
    CHECK(positions->body.find("<Position") != std::string::npos);
    CHECK(positions->body.find("<Execution") == std::string::npos);
    CHECK(validates(rig.get("/current?path=//Axes")->body, "Streams"));

    // /sample: consecutive calls chain through nextSequence with no gap.
    // Started a thousand observations back from a fresh /current, not at its
    // firstSequence: the machine keeps sampling, and under a slow build
    // (TSan) the oldest observation of a document fetched a few xmllint runs
    // earlier can be out of the buffer by the time /sample asks for it.
    const auto fresh = rig.get("/current");
    REQUIRE(fresh);
    const std::uint64_t first = std::stoull(attribute(fresh->body, "firstSequence"));
    const std::uint64_t last = std::stoull(attribute(fresh->body, "lastSequence"));
    std::uint64_t from = std::max(first, last > 1000 ? last - 1000 : first);
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
    // From the newest observation of a fresh document (not the `from` of the
    // /sample calls above, which the buffer may have dropped since).
    const auto latest = rig.get("/gbt18759/current");
    REQUIRE(latest);
    const auto enquired = rig.get("/gbt18759/enquire?From=" + attribute(latest->body, "lastSequence") + "&Count=5");
    REQUIRE(enquired);
    INFO(enquired->body.substr(0, 600));
    CHECK(enquired->status == 200);
    CHECK(validates(enquired->body, "Streams"));
    auto write = rig.http->Post("/gbt18759/write",
                                "<DataWriteRequest><Header version=\"1.0\" sender=\"itest\"/><Operation command=\"SET\">"
                                "<Value dataItemId=\"spindle_override\">87</Value></Operation></DataWriteRequest>",
                                "application/xml");
    REQUIRE(write);
    CHECK(write->status == 200);
    CHECK(rig.query_one("spindle_override") == 87);
    auto write_by_mt_id = rig.http->Post("/gbt18759/write",
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
    auto refused =
        rig.http->Post(("/nclink/v1/devices/" + kDev + "/set").c_str(), R"({"id":"x_position","value":1})", "application/json");
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
    REQUIRE(eventually(
        [&] {
            auto r = rig.get("/current?path=" + encoded("//DataItem[@id=\"" + kDev + ".x_position\"]"));
            return r && r->body.find(">AVAILABLE</Availability>") == std::string::npos &&
                   r->body.find("<Position") != std::string::npos && r->body.find(">UNAVAILABLE</Position>") == std::string::npos;
        },
        20s));
}

// A link that hangs (a dead broker node of a cluster, a pulled cable) gives
// no last will for 1.5 keep-alives, or never: the bridge's liveness check
// must notice the silence itself (docs/bridge.md "A machine that falls
// silent"). The proxy holds the adapter's connection open and passes
// nothing; its keep-alive of 60 s keeps the broker from ending it (and
// publishing the will) while the test runs. With an agent in the plant, the
// bridge's question may be answered by the agent in the adapter's place
// (DEV_UNREACHABLE, 8.3.5): no sign of the adapter either. A raw MQTT peer
// answers so in the second section.
namespace {
// Answers every Query the bridge `ex` sends `dev` as an agent does for an
// adapter it has as offline.
struct UnreachableAnswers {
    UnreachableAnswers(const std::string& broker_url, const std::string& dev, const std::string& ex) {
        MqttOptions m;
        m.broker_url = broker_url;
        m.client_id = "unreachable-answers";
        transport = make_mqtt_transport(m).value();
        transport->set_message_handler([this, dev, ex](const Message& request) {
            const Json query = Json::parse(request.payload, nullptr, false);
            if (!query.is_object()) return;
            const Json answer = {{"@id", query.value("@id", Json())}, {"code", "NG"},    {"error", 202},
                                 {"reason", "DEV_UNREACHABLE"},       {"dev_uuid", dev}, {"privateInfo", {{"agent", "fake"}}}};
            if (transport->publish(Message{topics::query_response(dev, ex), answer.dump(), 1, false})) ++answered;
        });
        REQUIRE(transport->subscribe({topics::query_request(dev, ex)}, 1));
        REQUIRE(transport->start());
        REQUIRE(eventually([&] { return transport->state() == LinkState::connected; }));
    }
    ~UnreachableAnswers() { transport->stop(std::chrono::milliseconds(0)); }
    std::unique_ptr<Transport> transport;
    std::atomic<int> answered{0};
};
}  // namespace

TEST_CASE("an adapter whose link hangs turns UNAVAILABLE by the liveness check and AVAILABLE once it answers") {
    const bool agent_answers = GENERATE(false, true);
    INFO((agent_answers ? "an agent answers DEV_UNREACHABLE in the adapter's place" : "nobody answers"));
    nclink::test::SimMillRig rig;
    nclink::test::AckDroppingProxy proxy(rig.broker.port());
    rig.config.broker_url = proxy.url();
    rig.config.keep_alive = 60s;
    rig.start();

    // What the broker says of the adapter: its state stays online throughout.
    auto watcher = rig.make_client("state-watcher");
    std::mutex states_mutex;
    std::vector<std::string> states;
    REQUIRE(watcher->subscribe_state(kDev, [&](const NotifyState& s) {
        std::lock_guard<std::mutex> lock(states_mutex);
        states.push_back(s.state);
    }));

    bridge::BridgeConfig c;
    c.broker_url = rig.broker.url();
    c.http_port = 0;
    c.shdr_port = 0;
    c.ex_cid = "bridge-liveness";
    c.adapter_liveness = 1000ms;
    c.request_timeout = 500ms;
    bridge::Bridge the_bridge(c, Logger{});
    REQUIRE(the_bridge.start().ok());
    httplib::Client http("127.0.0.1", the_bridge.http_port());
    http.set_read_timeout(10, 0);
    const auto get = [&](const std::string& path) {
        auto r = http.Get(path.c_str());
        return r && r->status == 200 ? r->body : std::string();
    };
    const std::string position_path = "/current?path=" + encoded("//DataItem[@id=\"" + kDev + ".x_position\"]");
    // The device AVAILABLE and the mill's x position with a value.
    const auto available = [&] {
        const std::string position = get(position_path);
        return get("/current").find(">AVAILABLE</Availability>") != std::string::npos &&
               position.find("<Position") != std::string::npos && position.find(">UNAVAILABLE</Position>") == std::string::npos;
    };
    REQUIRE(eventually(available, 20s));

    proxy.hold_now();
    std::unique_ptr<UnreachableAnswers> agent;
    if (agent_answers) agent = std::make_unique<UnreachableAnswers>(rig.broker.url(), kDev, c.ex_cid);
    std::string body;
    REQUIRE(eventually(
        [&] {
            body = get("/current");
            return body.find(">UNAVAILABLE</Availability>") != std::string::npos;
        },
        20s));
    INFO(body);
    CHECK(validates(body, "Streams"));
    CHECK(get(position_path).find(">UNAVAILABLE</Position>") != std::string::npos);
    // The bridge concluded it alone: the adapter never lost its connection
    // and the broker published no offline state.
    CHECK(rig.adapter->stats().transport.connects == 1);
    CHECK(proxy.connections() == 1);
    {
        std::lock_guard<std::mutex> lock(states_mutex);
        CHECK(std::count(states.begin(), states.end(), "offline") == 0);
    }

    if (agent) CHECK(agent->answered > 0);
    agent.reset();

    // The link passes again: the adapter's DTUs and answers bring it back.
    proxy.release();
    CHECK(eventually(available, 20s));
    the_bridge.stop();
    watcher->stop();
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
        const std::string snapshot =
            read_until(fd, [](const std::string& t) { return t.find("_avail|AVAILABLE\n") != std::string::npos; });
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
        const std::string live =
            read_until(fd, [](const std::string& t) { return t.find(":" + kDev + ".x_position|") != std::string::npos; });
        CHECK(live.find(":" + kDev + ".x_position|") != std::string::npos);
        ::close(fd);
    }
}

TEST_CASE("an agent reading the bridge's SHDR gets the mill's list and dict items with their value") {
    // What cppagent does with the bridge's /probe as Devices file and its
    // SHDR port as adapter (tests/support/shdr_agent.hpp): the tool table,
    // machine parameters and work coordinate systems arrive as NC-Link has them.
    Rig rig;
    // The list and dict items are polled: wait until the bridge has them.
    for (const char* id : {"tools", "parameters", "coordinates"})
        REQUIRE(eventually(
            [&] {
                auto r = rig.get("/current?path=" + encoded("//DataItem[@id=\"" + kDev + "." + id + "\"]"));
                return r && r->status == 200 && r->body.find("<Message") != std::string::npos &&
                       r->body.find(">UNAVAILABLE</Message>") == std::string::npos;
            },
            20s));
    const auto probe = rig.get("/probe");
    REQUIRE(probe);
    nclink::test::ShdrAgent agent(probe->body);
    int fd = connect_to(rig.the_bridge->shdr_port());
    // The snapshot until each of the three items' line is complete.
    agent.feed(read_until(fd, [](const std::string& t) {
        for (const char* id : {".tools|", ".parameters|", ".coordinates|"}) {
            const auto at = t.find(":" + kDev + id);
            if (at == std::string::npos || t.find('\n', at) == std::string::npos) return false;
        }
        return true;
    }));
    ::close(fd);
    CHECK(agent.problems().empty());
    for (const char* id : {"tools", "parameters", "coordinates"}) {
        INFO(id);
        const auto* c = agent.current(kDev + "." + id);
        REQUIRE(c);
        REQUIRE(c->available);
        CHECK(Json::parse(c->value) == rig.query_one(id));
    }
}

TEST_CASE("bridge shows other applications' method runs and events on the stream and the JSON API") {
    Rig rig;
    // The stream opened first: the run and the event must arrive live.
    std::mutex mutex;
    std::string received;
    std::atomic<bool> done{false};
    // Complete events only: a chunk may end inside one.
    auto complete = [](const std::string& text) {
        const auto end = text.rfind("\n\n");
        return end == std::string::npos ? std::string() : text.substr(0, end + 2);
    };
    // What the reader has found so far. Each chunk is searched from where
    // the last complete event ended, not the whole stream again: a reader
    // that rescanned megabytes of values per chunk fell behind the bridge
    // under TSan, and a stream that falls out of the buffer restarts with a
    // snapshot instead of the live events this test is about.
    std::size_t scanned = 0;
    bool seen[3] = {false, false, false};  // a method run, its result "finished", an event
    bool found_all = false;
    std::thread reader([&] {
        httplib::Client sse("127.0.0.1", rig.the_bridge->http_port());
        sse.set_read_timeout(5, 0);
        const auto deadline = std::chrono::steady_clock::now() + 60s;
        (void)sse.Get(("/nclink/v1/stream?dev=" + kDev).c_str(), [&](const char* data, size_t length) {
            std::lock_guard<std::mutex> lock(mutex);
            received.append(data, length);
            if (const auto end = received.rfind("\n\n"); end != std::string::npos && end + 2 > scanned) {
                static const char* const wanted[] = {"event: method\ndata: ", "\"result\":\"finished\"", "event: event\ndata: "};
                const std::string_view fresh(received.data() + scanned, end + 2 - scanned);
                for (int i = 0; i < 3; ++i) seen[i] = seen[i] || fresh.find(wanted[i]) != std::string_view::npos;
                scanned = end + 2;
                found_all = seen[0] && seen[1] && seen[2];
            }
            return !done && !found_all && std::chrono::steady_clock::now() < deadline;
        });
    });
    // Joined however the test ends: a failed REQUIRE with the reader still
    // running would otherwise terminate the process.
    struct JoinReader {
        std::atomic<bool>& done;
        std::thread& reader;
        ~JoinReader() {
            done = true;
            if (reader.joinable()) reader.join();
        }
    } join_reader{done, reader};
    auto read_so_far = [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return received;
    };
    REQUIRE(eventually(
        [&] {
            std::lock_guard<std::mutex> lock(mutex);
            return received.find("event: snapshot") != std::string::npos;
        },
        10s));

    // Another application calls methods (one refused) and registers an event that then fires.
    auto op = rig.make_client("operator");
    auto run = op->call_method(kDev, "cycle_start", Json::object());
    REQUIRE(run.ok());
    REQUIRE(run->result == "finished");
    auto refused = op->call_method(kDev, "self_destruct", nullptr);
    REQUIRE(refused.ok());
    REQUIRE(refused->status.error == 401);
    REQUIRE(op->set(kDev, {SetItem{"feed_override", Json{{"value", 100}}, std::nullopt, std::nullopt}}).ok());
    Client::EventRegistration registration;
    registration.id = "feed_override";
    registration.filters = {Json{{"type", "greater"}, {"value", 110}}};
    std::atomic<int> fired{0};
    auto event_id = op->register_event(kDev, registration, [&](const EventData&) { ++fired; });
    REQUIRE(event_id.ok());
    REQUIRE(op->set(kDev, {SetItem{"feed_override", Json{{"value", 120}}, std::nullopt, std::nullopt}}).ok());
    REQUIRE(eventually([&] { return fired.load() >= 1; }, 10s));

    // The stream: event: method with the caller, the call's @id, its result; event: event.
    REQUIRE(eventually(
        [&] {
            std::lock_guard<std::mutex> lock(mutex);
            return found_all;
        },
        30s));
    done = true;
    reader.join();
    const std::string stream = complete(read_so_far());
    std::vector<Json> methods, events;
    {
        std::istringstream lines(stream);
        std::string line, name;
        while (std::getline(lines, line)) {
            if (line.rfind("event: ", 0) == 0) name = line.substr(7);
            else if (line.rfind("data: ", 0) == 0 && name == "method") methods.push_back(Json::parse(line.substr(6)));
            else if (line.rfind("data: ", 0) == 0 && name == "event") events.push_back(Json::parse(line.substr(6)));
        }
    }
    auto finished = std::find_if(methods.begin(), methods.end(), [](const Json& m) {
        return m.value("method", "") == "cycle_start" && m.value("result", "") == "finished";
    });
    REQUIRE(finished != methods.end());
    CHECK((*finished)["dev"] == kDev);
    CHECK((*finished)["ex"] == "operator");
    CHECK((*finished)["code"] == "OK");
    CHECK((*finished)["call"].is_string());
    CHECK_FALSE((*finished)["call"].get<std::string>().empty());
    auto fired_event = std::find_if(events.begin(), events.end(), [](const Json& e) { return e["ex"] == "operator"; });
    REQUIRE(fired_event != events.end());
    CHECK((*fired_event)["item"] == "feed_override");
    CHECK((*fired_event)["value"] == 120);
    CHECK((*fired_event)["event"] == *event_id);
    for (const auto& e : events) CHECK(e["ex"] != "bridge-itest");  // the bridge's own change events are values

    // The JSON API keeps them: the refused call too, with its table-19 code.
    Json activity;
    REQUIRE(eventually(
        [&] {
            auto r = rig.get("/nclink/v1/devices/" + kDev + "/activity");
            if (!r || r->status != 200) return false;
            activity = Json::parse(r->body);
            for (const auto& m : activity["methods"])
                if (m.value("method", "") == "self_destruct" && m.value("result", "") == "error") return true;
            return false;
        },
        10s));
    bool logged_run = false, logged_refusal = false, logged_event = false;
    for (const auto& m : activity["methods"]) {
        logged_run = logged_run || (m["call"] == (*finished)["call"] && m["result"] == "finished");
        logged_refusal = logged_refusal || (m["method"] == "self_destruct" && m["code"] == "NG" && m["error"] == 401);
    }
    for (const auto& e : activity["events"]) logged_event = logged_event || (e["ex"] == "operator" && e["value"] == 120);
    CHECK(logged_run);
    CHECK(logged_refusal);
    CHECK(logged_event);
    auto unknown = rig.get("/nclink/v1/devices/nobody/activity");
    REQUIRE(unknown);
    CHECK(unknown->status == 404);

    // A stream opened now gets them in its snapshot.
    httplib::Client sse("127.0.0.1", rig.the_bridge->http_port());
    sse.set_read_timeout(10, 0);
    std::string later;
    (void)sse.Get(("/nclink/v1/stream?dev=" + kDev).c_str(), [&](const char* data, size_t length) {
        later.append(data, length);
        return later.find("\n\n") == std::string::npos;  // the first event: the snapshot
    });
    const std::string prefix = "event: snapshot\ndata: ";
    REQUIRE(later.rfind(prefix, 0) == 0);
    const Json snapshot = Json::parse(later.substr(prefix.size(), later.find('\n', prefix.size()) - prefix.size()));
    CHECK_FALSE(snapshot["methods"].empty());
    CHECK_FALSE(snapshot["events"].empty());
    REQUIRE(op->unregister_event(kDev, *event_id).ok());
    op->stop();
}
