// Method/Call, Method/Status and Method/Result through the adapter, over the
// loopback on a ManualClock (8.2.22-8.2.24).
#include "methods_fixture.hpp"

using namespace nclink;
using namespace nclink::test;

TEST_CASE("an accepted call publishes waiting and executing then its result with the return value") {
    MethodsFixture f;
    const std::string id = f.call("quick");
    const Json r = f.result(id);
    CHECK(r["guid"] == "test-dev");
    CHECK(r["id"] == "quick");
    CHECK(r["result"] == "finished");
    CHECK(r["code"] == "OK");
    CHECK(r["return"] == Json{{"ok", true}});
    const auto s = f.statuses(id);
    REQUIRE(s.size() == 2);  // the acceptance (8.2.22.3), then the driver running
    CHECK(s[0]["status"] == "waiting");
    CHECK(s[0]["guid"] == "test-dev");
    CHECK(s[0]["id"] == "quick");
    CHECK(s[1]["status"] == "executing");
}

TEST_CASE("answers mirror the call topic: a call without ex gets Status and Result without ex") {
    MethodsFixture f;
    const std::string id = f.call("quick", nullptr, "");
    CHECK(f.result(id, "")["result"] == "finished");
    CHECK(f.statuses(id, "").size() == 2);
    CHECK(f.dtus(topics::method_result("test-dev", std::string_view("app")), id).empty());
}

TEST_CASE("the args of the model are checked before the driver is called") {
    MethodsFixture f;
    SECTION("unknown method: 401") {
        const Json r = f.result(f.call("self_destruct"));
        CHECK(r["result"] == "error");
        CHECK(r["code"] == "NG");
        CHECK(r["error"] == 401);
        CHECK(r["reason"] == "Node not exists");
        CHECK(r["id"] == "self_destruct");
    }
    SECTION("a declared arg missing: 102, naming it") {
        const Json r = f.result(f.call("copy", Json{{"source", "/x"}}));
        CHECK(r["error"] == 102);
        CHECK(r["reason"] == "Parameter Missing");
        CHECK(r["privateInfo"]["message"].get<std::string>().find("destination") != std::string::npos);
    }
    SECTION("an arg the method does not declare: 409") {
        const Json r = f.result(f.call("quick", Json{{"speed", 5}}));
        CHECK(r["error"] == 409);
        CHECK(r["reason"] == "arguments nimiety");
    }
    SECTION("args that are not an object: 405") { CHECK(f.result(f.call("quick", Json::array({1, 2})))["error"] == 405); }
    SECTION("a call without id: 102; not JSON: 412") {
        f.app->send("Method/Call/test-dev/app", R"({"@id":"no-id","guid":"test-dev"})");
        CHECK(f.result("no-id")["error"] == 102);
        f.app->send("Method/Call/test-dev/app", "{oops");
        REQUIRE(eventually([&] { return f.app->on("Method/Result/test-dev/app").size() >= 2; }));
        CHECK(Json::parse(f.app->on("Method/Result/test-dev/app")[1].payload)["error"] == 412);
    }
    SECTION("defaults of array-declared args are filled in for the driver") {
        f.driver->release(10);
        CHECK(f.result(f.call("steps"))["return"] == Json{{"steps", 10}});
        REQUIRE(f.driver->call_count() == 1);
        CHECK(f.driver->calls_made()[0].second == Json{{"count", 10}});
    }
    CHECK(f.app->on("Method/Status/test-dev/app").size() == f.driver->call_count() * 2);  // a refused call has no Status
}

TEST_CASE("a driver error is a result error with its table-19 code and the driver's message") {
    MethodsFixture f;
    const Json r = f.result(f.call("fail"));
    CHECK(r["result"] == "error");
    CHECK(r["code"] == "NG");
    CHECK(r["error"] == 301);
    CHECK(r["reason"] == "Permission Denied");
    CHECK(r["privateInfo"]["message"] == "door open");
    const Json t = f.result(f.call("throws"));
    CHECK(t["error"] == 202);
    CHECK(t["privateInfo"]["message"] == "driver threw: boom");
    const Json u = f.result(f.call("unimplemented"));
    CHECK(u["error"] == 202);  // the Driver default: a driver without that method
    CHECK(f.adapter->stats().features["methods"]["errors"] == 3);
}

TEST_CASE("Method/Status goes out every status_period of the injected clock with the progress") {
    AdapterConfig c;
    c.methods.status_period = std::chrono::milliseconds(500);
    MethodsFixture f(c);
    const std::string id = f.call("steps", Json{{"count", 10}});
    f.status(id, 2);  // waiting, executing
    f.driver->release(3);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(f.statuses(id).size() == 2);  // the clock has not moved
    f.clock->advance(std::chrono::milliseconds(499));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(f.statuses(id).size() == 2);
    f.clock->advance(std::chrono::milliseconds(1));
    const Json third = f.status(id, 3);
    CHECK(third["status"] == "executing");
    CHECK(third["progress"] == 30);
    f.clock->advance(std::chrono::milliseconds(500));
    CHECK(f.status(id, 4)["progress"] == 30);
    // A jump over several periods gives one Status, not a burst.
    f.clock->advance(std::chrono::milliseconds(2000));
    f.status(id, 5);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(f.statuses(id).size() == 5);
    f.driver->release(7);
    CHECK(f.result(id)["return"] == Json{{"steps", 10}});
    const auto count = f.statuses(id).size();
    f.clock->advance(std::chrono::milliseconds(1000));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(f.statuses(id).size() == count);  // none after the Result
}

TEST_CASE("a running method does not hold up queries of the same serialized driver") {
    MethodsFixture f;
    const std::string id = f.call("steps", Json{{"count", 2}});
    f.wait_phase(id, "executing");
    const Json q = f.app->request(topics::query_request("test-dev", std::string_view("app")),
                                  topics::query_response("test-dev", std::string_view("app")),
                                  Json{{"@id", "q1"}, {"guid", "test-dev"}, {"ids", Json::array({Json{{"id", "pos"}}})}});
    CHECK(q["values"][0]["values"] == Json::array({1.5}));
    f.driver->release(2);
    CHECK(f.result(id)["result"] == "finished");
}

TEST_CASE("calls beyond max_running are refused 417 on Method/Result and accepted again once one ends") {
    AdapterConfig c;
    c.methods.max_running = 2;
    MethodsFixture f(c);
    const std::string a = f.call("steps", Json{{"count", 1}});
    const std::string b = f.call("steps", Json{{"count", 1}});
    f.wait_phase(a, "executing");
    f.wait_phase(b, "executing");
    const Json refused = f.result(f.call("quick"));
    CHECK(refused["result"] == "error");
    CHECK(refused["error"] == 417);
    CHECK(refused["reason"] == "Insufficient method resources");
    CHECK(f.adapter->stats().features["methods"]["running"] == 2);
    f.driver->release(1);
    REQUIRE(eventually(
        [&] { return f.dtus("Method/Result/test-dev/app", a).size() + f.dtus("Method/Result/test-dev/app", b).size() == 1; }));
    CHECK(f.result(f.call("quick"))["result"] == "finished");
    f.driver->release(1);
    f.result(a);
    f.result(b);
    CHECK(f.adapter->stats().features["methods"]["rejected_calls"] == 1);
}

TEST_CASE("max_running 0 refuses every call") {
    AdapterConfig c;
    c.methods.max_running = 0;
    MethodsFixture f(c);
    CHECK(f.result(f.call("quick"))["error"] == 417);
    CHECK(f.driver->call_count() == 0);
}

TEST_CASE("stopping the adapter cancels running methods and publishes their results") {
    MethodsFixture f;
    const std::string id = f.call("steps", Json{{"count", 5}});
    f.wait_phase(id, "executing");
    f.adapter->stop();
    const Json r = f.result(id);
    CHECK(r["result"] == "canceled");
    CHECK(r["return"] == Json{{"stopped_at", 0}});
}
