// Chapter 7 at the SDK boundary and the request/response forms of 8.2 and
// appendix A, through the wire.
#include "support/adapter_fixture.hpp"

#include <fstream>
#include <sstream>

using namespace nclink;
using namespace nclink::test;

TEST_CASE("a driver value breaking chapter 7 is answered NG with its table-19 code, counted once per value") {
    AdapterFixture f;
    {
        std::lock_guard<std::mutex> lock(f.driver->mutex);
        f.driver->values["pos"] = "12.5";     // a string for a POSITION (table 10: number)
        f.driver->values["status"] = "busy";  // not a STATUS of table 15
    }
    const Json r = f.query(Json::array({Json{{"id", "pos"}}, Json{{"id", "status"}}, Json{{"id", "ovr"}}}));
    const Json& v = r["values"];
    REQUIRE(v.size() == 3);
    CHECK(v[0]["code"] == "NG");
    CHECK(v[0]["error"] == 405);
    CHECK(v[0]["reason"] == "Value type error");
    CHECK_FALSE(v[0].contains("values"));
    CHECK(v[1]["error"] == 101);
    CHECK(v[2]["code"] == "OK");  // the other items are unaffected
    CHECK(f.adapter->stats().values_refused == 2);
    CHECK(f.adapter->stats().values_refused_items == 2);
    (void)f.query(Json::array({Json{{"id", "status"}}}));
    CHECK(f.adapter->stats().values_refused == 3);
    CHECK(f.adapter->stats().values_refused_items == 2);
    CHECK(to_json(f.adapter->stats())["values"]["refused"] == 3);
}

TEST_CASE("notify_value of a value breaking chapter 7 is refused and counted") {
    AdapterFixture f;
    f.adapter->notify_value("status", Json("holding"));
    CHECK(f.adapter->stats().values_refused == 0);
    f.adapter->notify_value("status", Json("spinning"));
    CHECK(f.adapter->stats().values_refused == 1);
}

TEST_CASE("a Set whose result breaks chapter 7 is refused before the driver writes") {
    AdapterFixture f;
    const Json r = f.set(Json::array({Json{{"id", "ovr"}, {"params", {{"value", -5}}}}}));  // FEED_OVERRIDE >= 0
    CHECK(r["results"][0]["error"] == 101);
    CHECK(f.driver->writes == 0);
}

TEST_CASE("Set: offset and length beside params (appendix A) are applied, results echo what was done") {
    AdapterFixture f;
    {
        std::lock_guard<std::mutex> lock(f.driver->mutex);
        f.driver->values["tools"] = Json::array({"abcdef", "x"});
    }
    const Json r = f.set(Json::array({
        Json{{"id", "tools"},
             {"offset", 2},
             {"length", 2},
             {"params", {{"operation", "set_value"}, {"index", 0}, {"value", "ZZ"}}}},
        Json{{"id", "tools"}, {"offset", 1}, {"params", {{"index", 0}, {"offset", 2}, {"value", "Q"}}}},
        Json{{"id", "ovr"}, {"params", {{"value", 90}}}},
    }));
    const Json& res = r["results"];
    REQUIRE(res.size() == 3);
    CHECK(res[0]["code"] == "OK");
    CHECK(res[0]["params"] == Json{{"operation", "set_value"}, {"index", 0}, {"offset", 2}, {"length", 2}});
    CHECK(f.driver->value("tools")[0] == "abZZef");        // not the whole element
    CHECK(res[1]["error"] == 409);                         // offset given twice, differently
    CHECK(res[2] == Json{{"id", "ovr"}, {"code", "OK"}});  // 8.2.14 example 1: nothing to echo
}

TEST_CASE("Query: appendix A forms (offset and length, get_attribute) are answered, not refused") {
    AdapterFixture f;
    {
        std::lock_guard<std::mutex> lock(f.driver->mutex);
        f.driver->values["tools"] = Json::array({"abcdef", Json::array({1, 2, 3}), 6});
    }
    const Json r = f.query(Json::array({
        Json{{"id", "tools"}, {"params", {{"indexes", {"0"}}, {"offset", 1}, {"length", 3}}}},
        Json{{"id", "tools"}, {"params", {{"operation", "get_value"}, {"indexes", {"1"}}, {"offset", 1}}}},
        Json{{"id", "tools"}, {"params", {{"indexes", {"2"}}, {"offset", 1}, {"length", 2}}}},
        Json{{"id", "tools"}, {"params", {{"operation", "get_attribute"}, {"indexes", {"0"}}}}},
        Json{{"id", "params"}, {"params", {{"operation", "get_attribute"}, {"keys", {"p1"}}}}},
        Json{{"id", "tools"}, {"params", {{"indexes", {"0"}}, {"offset", 4}, {"length", 5}}}},
    }));
    const Json& v = r["values"];
    REQUIRE(v.size() == 6);
    CHECK(v[0]["values"] == Json::array({"bcd"}));
    CHECK(v[1]["values"] == Json::array({Json::array({2, 3})}));
    CHECK(v[2]["values"] == Json::array({3}));  // 6 = 0b110: bits 1-2
    CHECK(v[3]["code"] == "OK");
    CHECK(v[4]["code"] == "OK");
    CHECK(v[5]["error"] == 101);  // beyond the element
}

TEST_CASE("Probe/Query returns the model file byte for byte, a Probe/Set text as sent") {
    AdapterFixture f;
    std::ifstream in(test_model_path(), std::ios::binary);
    std::stringstream file;
    file << in.rdbuf();
    f.app->send("Probe/Query/Request/test-dev/app", R"({"@id":"p"})");
    REQUIRE(eventually([&] { return !f.app->on("Probe/Query/Response/test-dev/app").empty(); }));
    const std::string payload = f.app->on("Probe/Query/Response/test-dev/app").front().payload;
    CHECK(payload.find(file.str()) != std::string::npos);
    CHECK(Json::parse(payload)["probe"]["devices"][0]["guid"] == "test-dev");

    // A model with a short version: "1.0" stays "1.0" in Probe/Query and Probe/Version.
    Json model = Json::parse(file.str());
    model["devices"][0]["version"] = "1.0";
    const Json set = f.app->request("Probe/Set/Request/test-dev/app", "Probe/Set/Response/test-dev/app",
                                    Json{{"@id", "ps"}, {"probe", model.dump(2)}});
    CHECK(set["code"] == "OK");
    CHECK(f.app->wait("Probe/Version/test-dev", 2)["version"] == "1.0");
    const Json probed =
        f.app->request("Probe/Query/Request/test-dev/app", "Probe/Query/Response/test-dev/app", Json{{"@id", "p2"}});
    CHECK(probed["probe"]["devices"][0]["version"] == "1.0");
}

TEST_CASE("a refused Probe/Set answers a table-19 reason, the problems in privateInfo") {
    AdapterFixture f;
    const Json r = f.app->request("Probe/Set/Request/test-dev/app", "Probe/Set/Response/test-dev/app",
                                  Json{{"@id", "bad"}, {"probe", Json::object()}});
    CHECK(r["code"] == "NG");
    CHECK(r["error"] == 412);
    CHECK(r["reason"] == "syntax error");
    CHECK_THAT(r["privateInfo"]["problems"].get<std::string>(), Catch::Contains("devices"));
}

TEST_CASE("refused Register/Event and Register/Sample answers carry id") {
    AdapterFixture f;
    const Json ev = f.app->request(
        "Register/Event/Request/test-dev/app", "Register/Event/Response/test-dev/app",
        Json{{"@id", "e"}, {"id", "nope"}, {"filters", Json::array({Json{{"type", "change"}}})}, {"triggerType", "always"}});
    CHECK(ev["code"] == "NG");
    CHECK(ev.contains("id"));
    const Json sa = f.app->request(
        "Register/Sample/Request/test-dev/app", "Register/Sample/Response/test-dev/app",
        Json{{"@id", "s"}, {"ids", Json::array({Json{{"id", "nope"}}})}, {"sampleInterval", 100}, {"uploadInterval", 1000}});
    CHECK(sa["code"] == "NG");
    CHECK(sa.contains("id"));
}
