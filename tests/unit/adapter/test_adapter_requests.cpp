// The adapter through the wire (loopback): Query, Set, Probe, error answers,
// the docs/wire.md rules (mirror topics, @id echo, retained and repeated requests).
// Compiled again, through a real mosquitto, into the adapter's integration
// tests (tests/integration/adapter/CMakeLists.txt): every data type and
// operation, every error code they reach, mirror topics with and without ex.
#include "support/adapter_fixture.hpp"

using namespace nclink;
using namespace nclink::test;

TEST_CASE("startup announces the adapter: online state, registration, version") {
    AdapterFixture f;
    const Json online = f.app->wait("Notify/State/test-dev");
    CHECK(online == Json{{"tid", "test-dev"}, {"state", "online"}});
#ifndef NCLINK_ADAPTER_TESTS_OVER_MOSQUITTO
    REQUIRE(f.broker.retained("Notify/State/test-dev").has_value());  // mosquitto: see itest_client's state test
#endif
    const Json reg = f.app->wait("Register/Request");
    CHECK(reg["cli_uuid"] == "test-dev");
    CHECK(reg.contains("@id"));
    const Json version = f.app->wait("Probe/Version/test-dev");
    CHECK(version["guid"] == "test-dev");
    CHECK(version["version"] == "1.0.0");
}

TEST_CASE("query answers one result per item, in order, from the driver and the SDK") {
    AdapterFixture f;
    const Json r = f.query(Json::array({
        Json{{"id", "pos"}},
        Json{{"id", "maker"}},
        Json{{"id", "nope"}},
        Json{{"id", "tools"}, {"params", {{"operation", "get_length"}}}},
        Json{{"id", "tools"}, {"params", {{"operation", "get_value"}, {"indexes", {"0", "1-2"}}}}},
        Json{{"id", "params"}, {"params", {{"operation", "get_keys"}}}},
        Json{{"id", "pos"}, {"params", {{"operation", "get_length"}}}},
        Json{{"id", "feed_ovr_cfg"}},
        Json{{"id", "pos"}, {"params", {{"operation", "get_value"}}}},
    }));
    CHECK(r["@id"] == "q1");
    CHECK(r["guid"] == "test-dev");
    const Json& v = r["values"];
    REQUIRE(v.size() == 9);
    CHECK(v[0] == Json{{"id", "pos"}, {"code", "OK"}, {"values", {12.5}}});
    CHECK(v[1]["values"] == Json::array({"ACME"}));  // fixed model value, served by the SDK
    CHECK(v[2]["code"] == "NG");
    CHECK(v[2]["error"] == 401);
    CHECK(v[2]["reason"] == "Node not exists");
    CHECK(v[3]["values"] == Json::array({3}));
    CHECK(v[3]["params"] == Json{{"operation", "get_length"}});  // params echoed
    CHECK(v[4]["values"].size() == 3);
    CHECK(v[4]["values"][1]["id"] == "T2");
    CHECK(v[5]["values"] == Json::array({"name", "p1", "p2"}));
    CHECK(v[6]["error"] == 406);
    CHECK(v[7]["values"] == Json::array({100}));
    // A driver item asked for whole with params: its value, the params echoed.
    CHECK(v[8] == Json{{"id", "pos"}, {"code", "OK"}, {"params", {{"operation", "get_value"}}}, {"values", {12.5}}});
}

TEST_CASE("set enforces setable, writes through the driver or the SDK store, one result per item") {
    AdapterFixture f;
    const Json r = f.set(Json::array({
        Json{{"id", "ovr"}, {"params", {{"value", 80}}}},
        Json{{"id", "status"}, {"params", {{"value", "free"}}}},
        Json{{"id", "tools"}, {"params", {{"operation", "set_value"}, {"index", 1}, {"value", Json{{"id", "T9"}}}}}},
        Json{{"id", "tools"}, {"params", {{"index", 7}, {"value", Json::object()}}}},
        Json{{"id", "params"}, {"params", {{"operation", "add"}, {"key", "p3"}, {"value", 3}}}},
        Json{{"id", "feed_ovr_cfg"}, {"params", {{"value", 55}}}},
        Json{{"id", "maker"}, {"params", {{"value", "EVIL"}}}},
        Json{{"id", "ghost"}, {"params", {{"value", 1}}}},
    }));
    const Json& res = r["results"];
    REQUIRE(res.size() == 8);
    CHECK(res[0] == Json{{"id", "ovr"}, {"code", "OK"}});
    CHECK(res[1]["error"] == 301);
    CHECK(res[1]["reason"] == "Permission Denied");
    CHECK(res[2]["code"] == "OK");
    CHECK(res[3]["error"] == 101);  // checked against the machine's current list
    CHECK(res[4]["code"] == "OK");
    CHECK(res[5]["code"] == "OK");
    CHECK(res[6]["error"] == 301);  // a fixed model value is not setable
    CHECK(res[7]["error"] == 401);

    CHECK(f.driver->value("ovr") == 80);
    CHECK(f.driver->value("tools")[1] == Json{{"id", "T9"}});
    CHECK(f.driver->value("params")["p3"] == 3);
    const Json q = f.query(Json::array({Json{{"id", "feed_ovr_cfg"}}, Json{{"id", "maker"}}}));
    CHECK(q["values"][0]["values"] == Json::array({55}));
    CHECK(q["values"][1]["values"] == Json::array({"ACME"}));
}

TEST_CASE("responses mirror the request topic, with and without ex") {
    AdapterFixture f;
    f.app->send("Query/Request/test-dev", R"({"@id":"plain","guid":"test-dev","ids":[{"id":"pos"}]})");
    CHECK(f.app->wait("Query/Response/test-dev")["@id"] == "plain");
    f.app->send("Query/Request/test-dev/mes-7", R"({"@id":"with-ex","guid":"test-dev","ids":[{"id":"pos"}]})");
    CHECK(f.app->wait("Query/Response/test-dev/mes-7")["@id"] == "with-ex");
    // A numeric @id comes back verbatim, as a number.
    f.app->send("Query/Request/test-dev/mes-7", R"({"@id":42,"ids":[{"id":"pos"}]})");
    CHECK(f.app->wait("Query/Response/test-dev/mes-7", 2)["@id"] == 42);
}

TEST_CASE("malformed requests get NG answers with the right code, the adapter keeps serving") {
    AdapterFixture f;
    const std::string reply = "Query/Response/test-dev/app";
    f.app->send("Query/Request/test-dev/app", "{this is not json");
    Json r = f.app->wait(reply, 1);
    CHECK(r["code"] == "NG");
    CHECK(r["error"] == 412);
    CHECK_FALSE(r.contains("@id"));
    f.app->send("Query/Request/test-dev/app", R"({"@id":"w","guid":"test-dev","values":[{"id":"pos"}]})");
    r = f.app->wait(reply, 2);
    CHECK(r["@id"] == "w");
    CHECK(r["error"] == 413);  // Set's key in a Query
    f.app->send("Query/Request/test-dev/app", R"({"@id":"m","guid":"test-dev"})");
    CHECK(f.app->wait(reply, 3)["error"] == 102);
    f.app->send("Query/Request/test-dev/app", R"({"@id":"t","ids":"pos"})");
    CHECK(f.app->wait(reply, 4)["error"] == 405);
    f.app->send("Set/Request/test-dev/app", R"([1,2,3])");
    CHECK(f.app->wait("Set/Response/test-dev/app")["error"] == 412);
    // A request without @id is still answered, without @id.
    f.app->send("Query/Request/test-dev/app", R"({"ids":[{"id":"pos"}]})");
    r = f.app->wait(reply, 5);
    CHECK_FALSE(r.contains("@id"));
    CHECK(r["values"][0]["code"] == "OK");
    CHECK(f.adapter->stats().rejected == 5);
    // Still serving.
    CHECK(f.query(Json::array({Json{{"id", "pos"}}}))["values"][0]["code"] == "OK");
}

TEST_CASE("a retained request is ignored, a repeated @id is answered once") {
    AdapterFixture f({}, false);
    // A client published a Set retained before the adapter (re)subscribed: the
    // broker replays it, flagged, on subscription. Acting on it would move the
    // machine again.
    f.app->send("Set/Request/test-dev/app", R"({"@id":"stale","values":[{"id":"ovr","params":{"value":1}}]})", true);
    REQUIRE(f.app->transport->flush(std::chrono::seconds(5)));  // at the broker, retained
    f.start();
    f.app->send("Set/Request/test-dev/app", R"({"@id":"once","values":[{"id":"ovr","params":{"value":70}}]})");
    f.app->send("Set/Request/test-dev/app", R"({"@id":"once","values":[{"id":"ovr","params":{"value":70}}]})");
    CHECK(f.app->wait("Set/Response/test-dev/app")["@id"] == "once");
    // Another request after them proves the duplicates were processed (and dropped).
    f.query(Json::array({Json{{"id", "pos"}}}));
    CHECK(f.app->on("Set/Response/test-dev/app").size() == 1);
    CHECK(f.driver->value("ovr") == 70);
    CHECK(f.adapter->stats().ignored_retained == 1);
    CHECK(f.adapter->stats().ignored_duplicates == 1);
    // The same @id from another application is a different request.
    f.app->send("Set/Request/test-dev/other", R"({"@id":"once","values":[{"id":"ovr","params":{"value":71}}]})");
    CHECK(f.app->wait("Set/Response/test-dev/other")["@id"] == "once");
}

// A Query is decoded on the transport thread by the streaming decoder when
// it can, else (here: a key given twice) by the tree decoder on the worker.
TEST_CASE("a Query is answered and its repeated @id dropped whichever decoder reads it") {
    AdapterFixture f;
    const std::string reply = "Query/Response/test-dev/app";
    const std::string streamed = R"({"@id":"s1","ids":[{"id":"pos"},"ovr"],"privateInfo":{"t":[1]}})";
    const std::string tree_only = R"({"@id":"t1","ids":[{"id":"nope","id":"pos"}]})";  // the tree keeps the last
    f.app->send("Query/Request/test-dev/app", streamed);
    f.app->send("Query/Request/test-dev/app", streamed);
    f.app->send("Query/Request/test-dev/app", tree_only);
    f.app->send("Query/Request/test-dev/app", tree_only);
    const Json first = f.app->wait(reply, 1);
    CHECK(first["@id"] == "s1");
    CHECK(first["values"][0]["id"] == "pos");
    CHECK(first["values"][0]["code"] == "OK");
    CHECK(first["values"][1]["id"] == "ovr");
    CHECK(first["values"][1]["code"] == "OK");
    const Json second = f.app->wait(reply, 2);
    CHECK(second["@id"] == "t1");
    CHECK(second["values"][0]["id"] == "pos");
    CHECK(second["values"][0]["code"] == "OK");
    // A request after them proves the repeats were processed (and dropped).
    f.query(Json::array({Json{{"id", "pos"}}}));
    CHECK(f.app->on(reply).size() == 3);
    CHECK(f.adapter->stats().ignored_duplicates == 2);
}

TEST_CASE("a repeated @id is handled again once the dedup window has passed") {
    AdapterFixture f;
    const Json body = Json{{"@id", "again"}, {"ids", Json::array({Json{{"id", "pos"}}})}};
    f.app->send("Query/Request/test-dev/app", body.dump());
    f.app->wait("Query/Response/test-dev/app", 1);
    f.clock->advance(f.config.dedup_window + std::chrono::milliseconds(1));
    f.app->send("Query/Request/test-dev/app", body.dump());
    f.app->wait("Query/Response/test-dev/app", 2);
}

TEST_CASE("a slow driver answers Timeout (203) per item, and SDK items still answer") {
    AdapterConfig c;
    c.driver_timeout = std::chrono::milliseconds(20);
    AdapterFixture f(c);
    f.driver->delay = std::chrono::milliseconds(300);
    const Json r = f.query(Json::array({Json{{"id", "pos"}}, Json{{"id", "maker"}}, Json{{"id", "status"}}}));
    CHECK(r["values"][0]["error"] == 203);
    CHECK(r["values"][0]["reason"] == "Timeout");
    CHECK(r["values"][1]["code"] == "OK");
    CHECK(r["values"][2]["error"] == 203);
    CHECK(f.adapter->stats().driver_timeouts >= 1);
    // The driver's late answer is dropped: the deadline already answered.
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    CHECK(f.app->on("Query/Response/test-dev/app").size() == 1);
    f.driver->delay = std::chrono::milliseconds(0);
}

TEST_CASE("a Set still queued behind a busy driver at its deadline answers 203 and is never written later") {
    AdapterConfig c;
    c.driver_timeout = std::chrono::milliseconds(60);
    AdapterFixture f(c);
    f.driver->delay = std::chrono::milliseconds(400);
    // A Query holds the (serialized) driver; the Set queues behind it.
    f.app->send("Query/Request/test-dev/app", R"({"@id":"slow","guid":"test-dev","ids":[{"id":"pos"}]})");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const Json r = f.set(Json::array(
        {Json{{"id", "ovr"}, {"params", {{"value", 80}}}}, Json{{"id", "feed_ovr_cfg"}, {"params", {{"value", 55}}}}}));
    CHECK(r["results"][0]["error"] == 203);
    CHECK(r["results"][0]["privateInfo"]["message"].get<std::string>().find("not written") != std::string::npos);
    CHECK(r["results"][1]["code"] == "OK");  // an SDK-held item does not wait for the driver
    // The driver gets free: the withdrawn Set does not reach it, nor answers twice.
    f.driver->delay = std::chrono::milliseconds(0);
    f.app->wait("Query/Response/test-dev/app", 1);                // the slow Query's 203, from its own deadline
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // its read (400 ms) is over
    CHECK(f.query(Json::array({Json{{"id", "ovr"}}}))["values"][0]["values"] == Json::array({100}));
    CHECK(f.driver->write_count() == 0);
    CHECK(f.app->on("Set/Response/test-dev/app").size() == 1);
}

TEST_CASE("a Set the driver is still writing at its deadline gets one 203 for the whole Set") {
    AdapterConfig c;
    c.driver_timeout = std::chrono::milliseconds(60);
    AdapterFixture f(c);
    f.driver->write_delay = std::chrono::milliseconds(300);
    const Json r = f.set(Json::array({Json{{"id", "ovr"}, {"params", {{"value", 80}}}}}));
    CHECK(r["error"] == 203);
    CHECK(r["privateInfo"]["message"].get<std::string>().find("may still take effect") != std::string::npos);
    // The write was under way: it lands, and its late answer is dropped.
    f.driver->write_delay = std::chrono::milliseconds(0);
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (f.driver->write_count() == 0 && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    CHECK(f.driver->write_count() == 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the worker drops its late answer
    CHECK(f.query(Json::array({Json{{"id", "ovr"}}}))["values"][0]["values"] == Json::array({80}));
    CHECK(f.app->on("Set/Response/test-dev/app").size() == 1);
    CHECK(f.adapter->stats().driver_timeouts >= 1);
}

TEST_CASE("an adapter stopped while a Query is stuck in the driver shuts down and stays quiet") {
    AdapterConfig c;
    c.driver_timeout = std::chrono::milliseconds(100);  // also the grace stop() gives a driver call
    auto f = std::make_unique<AdapterFixture>(c);
    f->driver->delay = std::chrono::milliseconds(600);
    f->app->send("Query/Request/test-dev/app", R"({"@id":"stuck","guid":"test-dev","ids":[{"id":"pos"}]})");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the read is under way
    auto driver = f->driver;
    f->adapter->stop(std::chrono::milliseconds(10));
    f.reset();  // the adapter is gone while its driver worker is still inside read()
    std::this_thread::sleep_for(std::chrono::milliseconds(700));  // the read returns into nothing
    CHECK(driver->delay.load() == std::chrono::milliseconds(600));
}

TEST_CASE("requests of features the adapter does not run are answered NG 202, never silence") {
    AdapterFixture f;
    f.app->send("Method/Call/test-dev/app", R"({"@id":"mc","guid":"test-dev","id":"m_start"})");
    const Json r = f.app->wait("Method/Result/test-dev/app");
    CHECK(r["@id"] == "mc");
    CHECK(r["code"] == "NG");
    CHECK(r["error"] == 202);
}

// A Set that decodes is decoded on the transport thread (which reads its
// @id anyway) and handed to the worker; one the decoder refuses is decoded
// again on the worker, which answers the refusal. Both are deduplicated.
TEST_CASE("a Set is answered and its repeated @id dropped whether the transport thread decoded it or not") {
    AdapterFixture f;
    const std::string reply = "Set/Response/test-dev/app";
    const std::string good = R"({"@id":"g1","values":[{"id":"ovr","params":{"value":55}}]})";
    const std::string refused = R"({"@id":"b1","values":"ovr"})";  // values not an array: 405
    f.app->send("Set/Request/test-dev/app", good);
    f.app->send("Set/Request/test-dev/app", good);
    f.app->send("Set/Request/test-dev/app", refused);
    f.app->send("Set/Request/test-dev/app", refused);
    const Json first = f.app->wait(reply, 1);
    CHECK(first["@id"] == "g1");
    CHECK(first["results"] == Json::array({Json{{"id", "ovr"}, {"code", "OK"}}}));
    const Json second = f.app->wait(reply, 2);
    CHECK(second["@id"] == "b1");
    CHECK(second["code"] == "NG");
    CHECK(second["error"] == 405);
    // A request after them proves the repeats were processed (and dropped).
    f.query(Json::array({Json{{"id", "pos"}}}));
    CHECK(f.app->on(reply).size() == 2);
    CHECK(f.driver->value("ovr") == 55);
    CHECK(f.adapter->stats().ignored_duplicates == 2);
    CHECK(f.adapter->stats().rejected == 1);
}
