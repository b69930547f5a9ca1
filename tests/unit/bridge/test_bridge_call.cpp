// The bridge's POST /nclink/v1/devices/{dev}/call (docs/bridge.md "JSON
// API"): an NC-Link Method/Call answered at its Method/Result, for the OPC
// UA server's Methods. A real adapter with methods the test steps
// (tests/unit/methods), a real client, on the in-process loopback; the
// bridge's HTTP server and a real HTTP client on loopback.
#include "bridge/bridge_store.hpp"
#include "bridge/follower.hpp"
#include "bridge/json_api.hpp"
#include "http/http_server.hpp"

#include "../methods/methods_fixture.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

using namespace nclink;
using namespace nclink::bridge;
using namespace std::chrono_literals;

namespace {

struct CallRig {
    CallRig() : store(64, "test", 7) {
        store.add_device("test-dev");
        LoopbackOptions o;
        o.client_id = "bridge";
        ClientOptions options;
        options.ex_cid = "bridge";
        options.default_timeout = 2000ms;
        auto c = Client::create(make_loopback_transport(methods.broker, o), options);
        REQUIRE(c);
        client = std::move(*c);
        REQUIRE(client->start().ok());
        REQUIRE(client->wait_connected(5000ms));
        FollowerOptions f;
        f.devices = {"test-dev"};
        f.request_timeout = 2000ms;
        follower = std::make_unique<Follower>(*client, store, f);
        api = std::make_unique<JsonApi>(store, *follower, 1000ms);
        http::HttpOptions h;
        h.workers = 4;
        server = std::make_unique<http::HttpServer>(h);
        api->install(*server);
        REQUIRE(server->start().ok());
        http_client = std::make_unique<httplib::Client>("127.0.0.1", server->port());
        http_client->set_read_timeout(30, 0);
    }
    ~CallRig() {
        server->stop();
        client->stop();
    }
    /// POST .../call -> (HTTP status, body as JSON).
    std::pair<int, Json> call(const std::string& dev, const Json& body) {
        auto r = http_client->Post(("/nclink/v1/devices/" + dev + "/call").c_str(), body.dump(), "application/json");
        REQUIRE(r);
        return {r->status, Json::parse(r->body, nullptr, false)};
    }

    test::MethodsFixture methods;
    BridgeStore store;
    std::unique_ptr<Client> client;
    std::unique_ptr<Follower> follower;
    std::unique_ptr<JsonApi> api;
    std::unique_ptr<http::HttpServer> server;
    std::unique_ptr<httplib::Client> http_client;
};

}  // namespace

TEST_CASE("bridge call: a METHOD runs as NC-Link Method/Call and is answered with its Method/Result") {
    CallRig rig;
    auto [status, answer] = rig.call("test-dev", Json{{"method", "quick"}, {"args", Json::object()}});
    CHECK(status == 200);
    CHECK(answer["code"] == "OK");
    CHECK(answer["result"] == "finished");
    CHECK(answer["return"] == Json{{"ok", true}});
    REQUIRE(rig.methods.driver->call_count() == 1);
    CHECK(rig.methods.driver->calls_made().front().first == "quick");

    // A run that takes longer than a request timeout: its statuses keep the
    // call alive, and the answer comes at its result.
    std::thread releaser([&] {
        std::this_thread::sleep_for(300ms);
        rig.methods.driver->release(3);
    });
    std::tie(status, answer) = rig.call("test-dev", Json{{"method", "steps"}, {"args", Json{{"count", 3}}}, {"timeout_ms", 20000}});
    releaser.join();
    CHECK(status == 200);
    CHECK(answer["result"] == "finished");
    CHECK(answer["return"] == Json{{"steps", 3}});
}

TEST_CASE("bridge call: a refused call carries its table-19 code, a run past timeout_ms is NG 203 (504)") {
    CallRig rig;
    auto [status, answer] = rig.call("test-dev", Json{{"method", "no_such_method"}});
    CHECK(status == 200);
    CHECK(answer["code"] == "NG");
    CHECK(answer["result"] == "error");
    CHECK(answer["error"] == 401);
    std::tie(status, answer) = rig.call("test-dev", Json{{"method", "copy"}, {"args", Json{{"source", "/a"}}}});
    CHECK(answer["error"] == 102);  // a declared arg missing
    std::tie(status, answer) = rig.call("test-dev", Json{{"method", "fail"}});
    CHECK(answer["code"] == "NG");
    CHECK(answer["error"] == 301);

    // steps waits for permits the test never gives within 300 ms.
    std::tie(status, answer) = rig.call("test-dev", Json{{"method", "steps"}, {"args", Json{{"count", 1}}}, {"timeout_ms", 300}});
    CHECK(status == 504);
    CHECK(answer["code"] == "NG");
    CHECK(answer["error"] == 203);
    rig.methods.driver->release(1);

    // Malformed requests, unknown devices: plain errors, and the bridge keeps serving.
    CHECK(rig.call("test-dev", Json{{"args", Json::object()}}).first == 400);
    CHECK(rig.call("test-dev", Json{{"method", "quick"}, {"args", Json::array()}}).first == 400);
    CHECK(rig.call("test-dev", Json{{"method", "quick"}, {"timeout_ms", 0}}).first == 400);
    CHECK(rig.call("test-dev", Json{{"method", "quick"}, {"timeout_ms", "x"}}).first == 400);
    CHECK(rig.call("no-such-dev", Json{{"method", "quick"}}).first == 404);
    auto raw = rig.http_client->Post("/nclink/v1/devices/test-dev/call", "{not json", "application/json");
    REQUIRE(raw);
    CHECK(raw->status == 400);
    CHECK(rig.call("test-dev", Json{{"method", "quick"}}).second["result"] == "finished");
}
