// GB/T 18759.6 6.2.3-6.2.4 and 6.3.4: a malformed value of any table 7
// (snapshot: Path, At, Count) or table 8 (enquire: Path, Interval, From,
// Count) parameter is answered with the error document (MTConnectError, its
// errorCode and HTTP status) on every route that takes it, through the real
// HTTP server and a real HTTP client on loopback, and the bridge keeps
// serving. No broker: the store is filled by hand, the follower is never started.
#include "bridge/follower.hpp"
#include "bridge/gbt_api.hpp"
#include "bridge/mtconnect_api.hpp"
#include "http/http_server.hpp"

#include "support/recording_transport.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

using namespace nclink;
using namespace nclink::bridge;

namespace {

const char* kModel = R"({
  "id": "root", "type": "NC_LINK_ROOT", "version": "1.0",
  "devices": [{
    "id": "mill", "name": "Mill", "type": "MACHINE", "guid": "mill-01", "version": "1.0",
    "components": [{
      "id": "axis_x", "type": "AXIS", "number": "X",
      "dataItems": [{"id": "x_position", "type": "POSITION", "units": "mm"}]
    }]
  }]
})";

bool valid_error(const std::string& xml) {
    const char* env = std::getenv("NCLINK_SHARED_DIR");
    const std::string xsd =
        std::string(env && *env ? env : NCLINK_SHARED_DIR) + "/interop/mtconnect-schema/MTConnectError_1.4_1.0.xsd";
    if (!std::filesystem::exists(xsd) || std::system("command -v xmllint >/dev/null 2>&1") != 0) {
        WARN("MTConnect schemas or xmllint absent: " << xsd << " not checked");
        return true;
    }
    const auto file = std::filesystem::temp_directory_path() / ("nclink-gbt-params-" + std::to_string(::getpid()) + ".xml");
    std::ofstream(file) << xml;
    const int rc = std::system(("xmllint --nonet --noout --schema " + xsd + " " + file.string() + " >/dev/null 2>&1").c_str());
    std::filesystem::remove(file);
    return rc == 0;
}

struct Served {
    Served() : store(64, "test", 7), mtconnect(store) {
        store.add_device("mill-01");
        REQUIRE(store.set_model("mill-01", Json::parse(kModel)).ok());
        store.set_state("mill-01", "online");
        for (int i = 0; i < 10; ++i) store.update("mill-01", "x_position", 1.0 + i, 1700000000000 + i);
        ClientOptions options;
        options.ex_cid = "gbt-params";
        auto c = Client::create(std::make_unique<test::RecordingTransport>(), options);
        REQUIRE(c);
        client = std::move(*c);
        follower = std::make_unique<Follower>(*client, store, FollowerOptions{});
        gbt = std::make_unique<GbtApi>(store, mtconnect, *follower);
        http::HttpOptions o;
        o.workers = 4;
        server = std::make_unique<http::HttpServer>(o);
        mtconnect.install(*server);
        gbt->install(*server);
        REQUIRE(server->start().ok());
        http_client = std::make_unique<httplib::Client>("127.0.0.1", server->port());
        http_client->set_read_timeout(10, 0);
    }
    ~Served() { server->stop(); }

    BridgeStore store;
    MtConnectApi mtconnect;
    std::unique_ptr<Client> client;
    std::unique_ptr<Follower> follower;
    std::unique_ptr<GbtApi> gbt;
    std::unique_ptr<http::HttpServer> server;
    std::unique_ptr<httplib::Client> http_client;
};

}  // namespace

TEST_CASE("GB/T 18759.6: a malformed table 7 or table 8 value gets the error document on every route") {
    Served s;
    struct Bad {
        const char* query;  // already percent-encoded
        int status;
        const char* code;
    };
    // Table 7 (snapshot) and the parameters both tables share.
    const std::vector<Bad> snapshot = {
        {"Count=abc", 400, "INVALID_REQUEST"},
        {"Count=", 400, "INVALID_REQUEST"},
        {"Count=1.5", 400, "INVALID_REQUEST"},
        {"Count=-3", 400, "OUT_OF_RANGE"},
        {"Count=0", 400, "OUT_OF_RANGE"},
        {"Count=65", 400, "OUT_OF_RANGE"},  // above bufferSize 64
        {"Count=99999999999999999999999", 400, "OUT_OF_RANGE"},
        {"Count=5&Count=abc", 400, "INVALID_REQUEST"},  // a bad value beside a good one
        {"count=5&Count=6", 400, "INVALID_REQUEST"},    // two different values
        {"At=abc", 400, "INVALID_REQUEST"},
        {"At=-1", 400, "OUT_OF_RANGE"},
        {"At=0", 400, "OUT_OF_RANGE"},       // before firstSequence
        {"At=100000", 400, "OUT_OF_RANGE"},  // after lastSequence
        {"At=2&Interval=10", 400, "INVALID_REQUEST"},
        {"Path=%2F%2FDataItem%5B", 400, "INVALID_PATH"},  // //DataItem[
        {"Path=", 400, "INVALID_PATH"},
        {"Path=%2F%2FNothing", 400, "INVALID_PATH"},
        {"Path=%2F%2FLinear%00garbage", 400, "INVALID_PATH"},  // NUL: libxml2 would read only its head
        {"Path=%2F%2FLinear&Path=%2F%2FAxes", 400, "INVALID_REQUEST"},
        {"Interval=abc", 400, "INVALID_REQUEST"},
        {"Interval=-10", 400, "OUT_OF_RANGE"},
        {"Interval=999999999999", 400, "OUT_OF_RANGE"},
    };
    // Table 8 (enquire).
    const std::vector<Bad> enquire = {
        {"From=abc", 400, "INVALID_REQUEST"},
        {"From=", 400, "INVALID_REQUEST"},
        {"From=-1", 400, "OUT_OF_RANGE"},
        {"From=0", 400, "OUT_OF_RANGE"},
        {"From=100000", 400, "OUT_OF_RANGE"},  // after nextSequence
        {"From=1&From=x", 400, "INVALID_REQUEST"},
        {"Count=abc", 400, "INVALID_REQUEST"},
        {"Count=0", 400, "OUT_OF_RANGE"},
        {"Count=65", 400, "OUT_OF_RANGE"},
        {"Interval=abc", 400, "INVALID_REQUEST"},
        {"Interval=-10", 400, "OUT_OF_RANGE"},
        {"Interval=1.5", 400, "INVALID_REQUEST"},
        {"Path=%2F%2FDataItem%5B", 400, "INVALID_PATH"},
        {"Path=", 400, "INVALID_PATH"},
        {"Path=count(%2F%2FDataItem)", 400, "INVALID_PATH"},  // parses, but no node-set
        {"Path=%2F%2FLinear%00garbage", 400, "INVALID_PATH"},
    };
    auto check = [&](const std::string& route, const std::vector<Bad>& cases) {
        for (const auto& bad : cases) {
            const std::string target = route + "?" + bad.query;
            INFO(target);
            auto r = s.http_client->Get(target.c_str());
            REQUIRE(r);
            CHECK(r->status == bad.status);
            CHECK(r->body.find("<MTConnectError") != std::string::npos);
            CHECK(r->body.find(std::string("errorCode=\"") + bad.code + "\"") != std::string::npos);
            CHECK(valid_error(r->body));
        }
    };
    for (const char* route : {"/gbt18759/current", "/gbt18759/Mill/current", "/gbt18759/mill-01/current"}) check(route, snapshot);
    for (const char* route : {"/gbt18759/enquire", "/gbt18759/Mill/enquire", "/gbt18759/mill-01/enquire"}) {
        check(route, enquire);
        // Interval and Path are table 8's too; At belongs to the snapshot only.
        check(route, {snapshot[snapshot.size() - 1], snapshot[snapshot.size() - 2], snapshot[snapshot.size() - 3]});
    }
    // The same parameters under part 1's spelling on the MTConnect routes.
    check("/current", {{"count=abc", 400, "INVALID_REQUEST"}, {"at=x", 400, "INVALID_REQUEST"}});
    check("/sample", {{"from=1&from=x", 400, "INVALID_REQUEST"}, {"path=%2F%2FLinear%00x", 400, "INVALID_PATH"}});

    // Good values still answer data, so the checks above are what refused.
    for (const char* ok :
         {"/gbt18759/current?Count=5", "/gbt18759/current?Path=%2F%2FLinear&At=3", "/gbt18759/Mill/current?Count=5&count=5",
          "/gbt18759/enquire?From=2&Count=3", "/gbt18759/mill-01/enquire?Path=%2F%2FLinear&From=1&Count=64"}) {
        INFO(ok);
        auto r = s.http_client->Get(ok);
        REQUIRE(r);
        CHECK(r->status == 200);
        CHECK(r->body.find("<MTConnectStreams") != std::string::npos);
    }
}
