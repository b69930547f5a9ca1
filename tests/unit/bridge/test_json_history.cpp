// GET /nclink/v1/devices/{dev}/history (docs/bridge.md "JSON API"): an
// item's observations still in the bridge's buffer, by time range, for the
// OPC UA server's HistoryRead. The store filled by hand; the real HTTP server
// and client on loopback.
#include "bridge/bridge_store.hpp"
#include "bridge/follower.hpp"
#include "bridge/json_api.hpp"
#include "http/http_server.hpp"

#include "support/recording_transport.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

using namespace nclink;
using namespace nclink::bridge;
using namespace std::chrono_literals;

namespace {

const char* kModel = R"({
  "id": "root", "type": "NC_LINK_ROOT", "version": "1.0",
  "devices": [{"id": "mill", "name": "Mill", "type": "MACHINE", "guid": "mill-01", "version": "1.0",
    "components": [{"id": "axis_x", "type": "AXIS", "number": "X",
      "dataItems": [{"id": "x_position", "type": "POSITION", "units": "mm"}, {"id": "x_load", "type": "AXIS_LOAD", "units": "PERCENT"}]}]}]
})";

}  // namespace

TEST_CASE("bridge history: an item's buffered values by time range, oldest first, bounded") {
    BridgeStore store(64, "test", 7);
    store.add_device("mill-01");
    REQUIRE(store.set_model("mill-01", Json::parse(kModel)).ok());
    store.set_state("mill-01", "online");
    for (int i = 0; i < 5; ++i) {
        store.update("mill-01", "x_position", 10.0 + i, 1000 + i * 100);
        store.update("mill-01", "x_load", 50.0 + i, 1000 + i * 100 + 1);
    }
    ClientOptions options;
    options.ex_cid = "history";
    auto c = Client::create(std::make_unique<test::RecordingTransport>(), options);
    REQUIRE(c);
    Follower follower(**c, store, FollowerOptions{});
    JsonApi api(store, follower, 1000ms);
    http::HttpServer server(http::HttpOptions{});
    api.install(server);
    REQUIRE(server.start().ok());
    httplib::Client http("127.0.0.1", server.port());
    const auto get = [&](const std::string& path) {
        auto r = http.Get(path.c_str());
        REQUIRE(r);
        return std::make_pair(r->status, Json::parse(r->body, nullptr, false));
    };

    // (The store also holds the item's UNAVAILABLE from before the device
    // came online, stamped with the wall clock: outside 1000..2000.)
    auto [status, answer] = get("/nclink/v1/devices/mill-01/history?id=x_position&from=1000&to=2000");
    CHECK(status == 200);
    REQUIRE(answer["values"].size() == 5);
    CHECK(answer["values"][0] == Json{{"value", 10.0}, {"time", 1000}, {"quality", "good"}});
    CHECK(answer["values"][4]["value"] == 14.0);
    CHECK(answer.contains("oldest"));
    std::tie(status, answer) = get("/nclink/v1/devices/mill-01/history?id=x_position");
    CHECK(answer["values"].size() == 6);  // no range: all of it
    CHECK(answer["more"] == false);

    // by time range, both ends included
    std::tie(status, answer) = get("/nclink/v1/devices/mill-01/history?id=x_position&from=1300&to=1400");
    REQUIRE(answer["values"].size() == 2);
    CHECK(answer["values"][0]["time"] == 1300);
    CHECK(answer["values"][1]["time"] == 1400);
    std::tie(status, answer) = get("/nclink/v1/devices/mill-01/history?id=x_position&from=1301&to=1399");
    CHECK(answer["values"].empty());
    // bounded: max values, and "more" says there are others
    std::tie(status, answer) = get("/nclink/v1/devices/mill-01/history?id=x_load&max=2");
    REQUIRE(answer["values"].size() == 2);
    CHECK(answer["more"] == true);
    // UNAVAILABLE is a bad value
    store.set_state("mill-01", "offline");
    std::tie(status, answer) = get("/nclink/v1/devices/mill-01/history?id=x_position&from=0");
    CHECK(answer["values"].back()["quality"] == "bad");
    CHECK(answer["values"].back()["value"].is_null());

    // refused requests
    CHECK(get("/nclink/v1/devices/mill-01/history").first == 400);
    CHECK(get("/nclink/v1/devices/mill-01/history?id=x_position&from=abc").first == 400);
    CHECK(get("/nclink/v1/devices/mill-01/history?id=x_position&max=0").first == 400);
    CHECK(get("/nclink/v1/devices/mill-01/history?id=nothing").first == 404);
    CHECK(get("/nclink/v1/devices/nobody/history?id=x_position").first == 404);
    server.stop();
}
