// mtconnect_observations: NC-Link values as Streams observation text.
#include "mapping_test_util.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using nclink::test::fixed_options;
using nclink::test::load_mapping_model;
using nclink::test::parse_mapping_model;

namespace {

const MtConnectMapping& sim_mill() {
    static const MtConnectMapping mapping = [] {
        auto m = mtconnect_mapping(*load_mapping_model("sim-mill.json"), fixed_options());
        REQUIRE(m.ok());
        return std::move(m).value();
    }();
    return mapping;
}

MtObservation one(const char* item, const Json& value) {
    const MtDataItem* m = sim_mill().find(item);
    REQUIRE(m != nullptr);
    const auto observations = mtconnect_observations(*m, value);
    REQUIRE(observations.size() == 1);
    return observations[0];
}

}  // namespace

TEST_CASE("null is UNAVAILABLE for every data item") {
    for (const char* item : {"x_position", "status", "program", "part_count", "emergency_stop", "tools", "spindle_override"}) {
        INFO(item);
        const MtObservation o = one(item, nullptr);
        CHECK(o.value == "UNAVAILABLE");
        CHECK(o.exact);
    }
}

TEST_CASE("samples are numbers in MTConnect units") {
    CHECK(one("x_position", 12.5).value == "12.5");
    CHECK(one("x_position", 12.5).element == "Position");
    CHECK(one("x_position", -3).value == "-3");
    CHECK(one("x_position", "7.25").value == "7.25");
    CHECK(one("x_position", 1e20).value == "1E+20");
    CHECK(one("x_speed", 600).value == "10");  // mm/min -> MILLIMETER/SECOND
    CHECK(one("x_speed", 600).element == "AxisFeedrate");
    CHECK(one("spindle_speed", 1200).value == "1200");
    CHECK(one("spindle_speed", 1200).element == "RotaryVelocity");
}

TEST_CASE("a value a sample cannot carry is UNAVAILABLE and marked inexact") {
    for (const Json& bad : {Json(true), Json("fast"), Json::array({1, 2}), Json::object()}) {
        INFO(bad.dump());
        const MtObservation o = one("x_position", bad);
        CHECK(o.value == "UNAVAILABLE");
        CHECK_FALSE(o.exact);
    }
}

TEST_CASE("STATUS words become Execution values") {
    CHECK(one("status", "running").value == "ACTIVE");
    CHECK(one("status", "free").value == "READY");
    CHECK(one("status", "holding").value == "FEED_HOLD");
    CHECK(one("status", "holding").element == "Execution");
    const MtObservation unknown = one("status", "exploded");
    CHECK(unknown.value == "UNAVAILABLE");
    CHECK_FALSE(unknown.exact);
    CHECK(one("work_mode", "auto").value == "AUTOMATIC");
    CHECK(one("work_mode", "manual").value == "MANUAL");
    CHECK(one("work_mode", "manual").element == "ControllerMode");
}

TEST_CASE("booleans become the enumeration of their type") {
    CHECK(one("emergency_stop", true).value == "TRIGGERED");
    CHECK(one("emergency_stop", false).value == "ARMED");
    CHECK(one("emergency_stop", false).element == "EmergencyStop");
    CHECK(one("door_closed", true).value == "CLOSED");
    CHECK(one("door_closed", false).value == "OPEN");
    CHECK(one("spindle_mode", "forward").value == "CLOCKWISE");
    CHECK(one("spindle_mode", "reverse").value == "COUNTER_CLOCKWISE");
}

TEST_CASE("integer events accept integers and integer text only") {
    CHECK(one("part_count", "42").value == "42");
    CHECK(one("part_count", 42).value == "42");
    CHECK(one("part_count", " 7 ").value == "7");
    CHECK(one("part_count", 3.0).value == "3");
    CHECK_FALSE(one("part_count", "4.5").exact);
    CHECK_FALSE(one("part_count", "N100").exact);
    CHECK(one("line_number", "120").element == "LineNumber");
}

TEST_CASE("text events and fallbacks carry text and objects as JSON") {
    CHECK(one("program", "O1234").value == "O1234");
    CHECK(one("program", 1234).value == "1234");
    CHECK(one("tools", Json::array({Json{{"id", "T1"}}})).value == R"([{"id":"T1"}])");
    CHECK(one("tools", Json::array()).element == "Message");
    CHECK(one("cnc_version", "2.1").value == "2.1");
    CHECK(one("spindle_override", 110).value == "110");
    CHECK(one("spindle_override", 110).element == "RotaryVelocityOverride");
}

TEST_CASE("WARNING is a condition with one Fault per alarm or Normal or Unavailable") {
    const MtDataItem* warning = sim_mill().find("warning");
    REQUIRE(warning != nullptr);
    CHECK(warning->category == MtCategory::condition);
    CHECK(warning->element.empty());

    auto o = mtconnect_observations(*warning, nullptr);
    REQUIRE(o.size() == 1);
    CHECK(o[0].element == "Unavailable");
    for (const Json& none : {Json::object(), Json::array(), Json(false), Json("")}) {
        o = mtconnect_observations(*warning, none);
        REQUIRE(o.size() == 1);
        CHECK(o[0].element == "Normal");
    }
    o = mtconnect_observations(*warning, Json{{"number", "E1001"}, {"text", "Servo alarm"}});
    REQUIRE(o.size() == 1);
    CHECK(o[0].element == "Fault");
    CHECK(o[0].native_code == "E1001");
    CHECK(o[0].value == "Servo alarm");
    o = mtconnect_observations(*warning, Json::array({Json{{"number", 12}, {"text", "a"}}, Json{{"number", 13}, {"text", "b"}}}));
    REQUIRE(o.size() == 2);
    CHECK(o[0].native_code == "12");
    CHECK(o[1].value == "b");
}

TEST_CASE("items that are no DataItem have no observation") {
    const MtDataItem* manufacturer = sim_mill().find("manufacturer");
    REQUIRE(manufacturer != nullptr);
    CHECK(manufacturer->target == MtTarget::description_attribute);
    CHECK(mtconnect_observations(*manufacturer, "nclink").empty());
}

TEST_CASE("unit conversion of Fahrenheit and radians and kilowatt hours") {
    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","version":"1.0.0","guid":"g",
        "dataItems":[{"id":"t","type":"TEMPERATURE","units":"°F"},
                     {"id":"a","type":"ANGLE"},
                     {"id":"e","type":"ENERGY"},
                     {"id":"pf","type":"POWER_FACTOR"}]}]})");
    auto m = mtconnect_mapping(*model, fixed_options());
    REQUIRE(m.ok());
    const auto value = [&](const char* id, const Json& v) { return mtconnect_observations(*m->find(id), v).at(0).value; };
    CHECK(m->find("t")->units == "CELSIUS");
    CHECK(m->find("t")->native_units == "FAHRENHEIT");
    CHECK(value("t", 212) == "100");
    CHECK(m->find("a")->units == "DEGREE");
    CHECK(std::stod(value("a", 3.141592653589793)) == Approx(180));
    CHECK(value("e", 1) == "3600000");
    CHECK(m->find("pf")->units == "PERCENT");
    CHECK(value("pf", 0.5) == "50");
}
