// Method/Control/Request and Method/Control/Response (8.2.25-8.2.26).
#include "methods_fixture.hpp"

using namespace nclink;
using namespace nclink::test;

TEST_CASE("stop pauses at the next checkpoint with Status stopped and resume continues") {
    MethodsFixture f;
    const std::string id = f.call("steps", Json{{"count", 4}});
    f.wait_phase(id, "executing");
    const Json ok = f.control("steps", "stop");
    CHECK(ok["code"] == "OK");
    CHECK(ok["id"] == "steps");
    CHECK(ok["guid"] == "test-dev");
    f.driver->release(1);  // the step under way ends; the next checkpoint pauses
    const Json stopped = f.wait_phase(id, "stopped");
    CHECK(stopped["progress"] == 25);
    f.driver->release(3);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(f.dtus("Method/Result/test-dev/app", id).empty());  // paused: permits do not move it
    f.clock->advance(std::chrono::milliseconds(500));
    CHECK(f.status(id, f.statuses(id).size() + 1)["status"] == "stopped");  // the periodic Status says so too
    CHECK(f.control("steps", "resume")["code"] == "OK");
    const Json r = f.result(id);
    CHECK(r["result"] == "finished");
    CHECK(r["return"] == Json{{"steps", 4}});
    const auto s = f.statuses(id);
    CHECK(s.back()["status"] == "executing");  // resumed before it finished
}

TEST_CASE("cancel ends a running or paused method with result canceled") {
    MethodsFixture f;
    SECTION("running") {
        const std::string id = f.call("steps", Json{{"count", 4}});
        f.wait_phase(id, "executing");
        CHECK(f.control("steps", "cancel")["code"] == "OK");
        const Json r = f.result(id);
        CHECK(r["result"] == "canceled");
        CHECK(r["code"] == "OK");
        CHECK(r["return"] == Json{{"stopped_at", 0}});
    }
    SECTION("paused") {
        const std::string id = f.call("steps", Json{{"count", 4}});
        f.wait_phase(id, "executing");
        f.control("steps", "stop");
        f.driver->release(1);
        f.wait_phase(id, "stopped");
        CHECK(f.control("steps", "cancel")["code"] == "OK");
        CHECK(f.result(id)["result"] == "canceled");
    }
    CHECK(f.adapter->stats().features["methods"]["canceled"] == 1);
}

TEST_CASE("control answers 418 for an action other than stop resume cancel and 401 for an unknown method") {
    MethodsFixture f;
    const std::string id = f.call("steps", Json{{"count", 1}});
    f.wait_phase(id, "executing");
    const Json bad = f.control("steps", "pause");
    CHECK(bad["code"] == "NG");
    CHECK(bad["error"] == 418);
    CHECK(bad["reason"] == "method action type error");
    const Json unknown = f.control("self_destruct", "stop");
    CHECK(unknown["error"] == 401);
    CHECK(unknown["id"] == "self_destruct");
    f.app->send("Method/Control/Request/test-dev/app", R"({"@id":"x","guid":"test-dev","id":"steps"})");
    REQUIRE(eventually([&] { return !f.dtus("Method/Control/Response/test-dev/app", "x").empty(); }));
    CHECK(f.dtus("Method/Control/Response/test-dev/app", "x")[0]["error"] == 102);  // no action
    f.driver->release(1);
    CHECK(f.result(id)["result"] == "finished");
}

TEST_CASE("control of a method that is not running answers NG 202 with the reason in privateInfo") {
    MethodsFixture f;
    const Json r = f.control("steps", "cancel");
    CHECK(r["code"] == "NG");
    CHECK(r["error"] == 202);
    CHECK(r["reason"] == "Unavailable");
    CHECK(r["privateInfo"]["message"] == "method steps is not running");
    f.result(f.call("quick"));
    CHECK(f.control("quick", "stop")["error"] == 202);  // finished already
}

TEST_CASE("control acts on the caller's own runs first and privateInfo call narrows to one call") {
    MethodsFixture f;
    const std::string a = f.call("steps", Json{{"count", 1}}, "app");
    const std::string b = f.call("steps", Json{{"count", 1}}, "other");
    const std::string c = f.call("steps", Json{{"count", 1}}, "app");
    f.wait_phase(a, "executing");
    f.wait_phase(c, "executing");
    REQUIRE(eventually([&] { return f.statuses(b, "other").size() >= 2; }));
    CHECK(f.control("steps", "cancel", "app", Json{{"call", a}})["code"] == "OK");
    CHECK(f.result(a)["result"] == "canceled");
    CHECK(f.control("steps", "cancel", "other")["code"] == "OK");  // its own: b only
    CHECK(f.result(b, "other")["result"] == "canceled");
    CHECK(f.dtus("Method/Result/test-dev/app", c).empty());
    CHECK(f.control("steps", "cancel", "operator")["code"] == "OK");  // no own run: everybody's
    CHECK(f.result(c)["result"] == "canceled");
}

TEST_CASE("a paused run of an application that went offline is cancelled, a running one finishes") {
    MethodsFixture f;
    const std::string paused = f.call("steps", Json{{"count", 2}}, "gone-app");
    REQUIRE(eventually([&] { return f.statuses(paused, "gone-app").size() >= 2; }));
    f.control("steps", "stop", "gone-app");
    f.driver->release(1);
    REQUIRE(eventually([&] {
        for (const auto& s : f.statuses(paused, "gone-app"))
            if (s["status"] == "stopped") return true;
        return false;
    }));
    const std::string running = f.call("quick", nullptr, "gone-app");
    f.app->send("Notify/State/gone-app", R"({"tid":"gone-app","state":"offline"})");
    CHECK(f.result(paused, "gone-app")["result"] == "canceled");
    CHECK(f.result(running, "gone-app")["result"] == "finished");
}
