// An observation's text as the NC-Link value (observation_values.hpp), the
// live value table and the SHDR line reader.
#include "mtconnect/live_values.hpp"
#include "mtconnect/observation_values.hpp"
#include "mtconnect/probe_document.hpp"
#include "mtconnect/reverse_mapping.hpp"
#include "mtconnect/shdr_line.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::mtconnect;

namespace {

const char* const kProbe = R"(<MTConnectDevices><Header instanceId="1"/><Devices>
<Device id="d" name="mill" uuid="u-1"><DataItems>
  <DataItem category="EVENT" id="avail" type="AVAILABILITY"/>
  <DataItem category="SAMPLE" id="xs" type="AXIS_FEEDRATE" subType="ACTUAL" units="MILLIMETER/SECOND" nativeUnits="MILLIMETER/MINUTE"/>
  <DataItem category="EVENT" id="door" type="DOOR_STATE"/>
  <DataItem category="EVENT" id="dir" type="DIRECTION" subType="ROTARY"/>
  <DataItem category="EVENT" id="tools" type="MESSAGE" subType="x:TOOL"/>
  <DataItem category="EVENT" id="limit" type="MESSAGE" subType="x:UPPER_LIMIT"><Constraints><Value>12000</Value></Constraints></DataItem>
  <DataItem category="EVENT" id="parts" type="PART_COUNT" subType="ALL"/>
  <DataItem category="SAMPLE" id="pos3" type="POSITION" subType="ACTUAL" units="MILLIMETER_3D"/>
  <DataItem category="CONDITION" id="sys" name="system" type="SYSTEM"/>
  <DataItem category="EVENT" id="msg" name="message" type="MESSAGE"/>
</DataItems></Device></Devices></MTConnectDevices>)";

ReverseModel model() {
    auto probe = read_probe(kProbe);
    REQUIRE(probe.ok());
    auto r = reverse_map(probe.value());
    REQUIRE(r.ok());
    return std::move(r).value();
}

}  // namespace

TEST_CASE("observation text becomes the NC-Link value by the item's rule") {
    const ReverseModel m = model();
    const ItemBinding& xs = *m.find_mt("xs");
    CHECK(xs.units == "MILLIMETER/MINUTE");                  // outside an axis AXIS_FEEDRATE has no row: the unit as spelt
    CHECK(value_of(xs, "10").get<double>() == Approx(600));  // 10 mm/s is 600 mm/min
    CHECK(value_of(xs, "UNAVAILABLE").is_null());
    CHECK(value_of(xs, "unavailable").is_null());
    CHECK(value_of(xs, "abc").is_null());
    CHECK(value_of(*m.find_mt("door"), "CLOSED") == Json(true));
    CHECK(value_of(*m.find_mt("door"), "OPEN") == Json(false));
    CHECK(value_of(*m.find_mt("door"), "UNAVAILABLE").is_null());
    // Appendix A maps the spindle's "stop" to UNAVAILABLE: read back as "stop".
    CHECK(value_of(*m.find_mt("dir"), "UNAVAILABLE") == Json("stop"));
    CHECK(value_of(*m.find_mt("dir"), "CLOCKWISE") == Json("forward"));
    // nclink's fallback of lists and objects is compact JSON text.
    CHECK(value_of(*m.find_mt("tools"), R"([{"id":"T1"}])") == Json::parse(R"([{"id":"T1"}])"));
    CHECK(value_of(*m.find_mt("tools"), "not json") == Json("not json"));
    CHECK(value_of(*m.find_mt("parts"), "17") == Json("17"));  // PART_COUNT is text in table 13
    const Json p3 = value_of(*m.find_mt("pos3"), "1 2.5 -3");
    REQUIRE(p3.is_array());
    CHECK(p3.size() == 3);
    CHECK(m.find_mt("limit")->fixed);
}

TEST_CASE("a condition's active alarms follow Normal, Warning, Fault and Unavailable") {
    ConditionAlarms a;
    CHECK(a.value().is_null());
    a.apply("Normal", "", "");
    CHECK(a.value() == Json::array());
    a.apply("Fault", "1001", "Spindle overload");
    a.apply("Warning", "E7", "Lube low");
    Json v = a.value();
    REQUIRE(v.size() == 2);
    CHECK(v[0] == Json{{"number", 1001}, {"text", "Spindle overload"}, {"level", "FAULT"}});
    CHECK(v[1] == Json{{"number", "E7"}, {"text", "Lube low"}, {"level", "WARNING"}});
    a.apply("Normal", "1001", "");
    CHECK(a.value().size() == 1);
    a.apply("Normal", "", "");
    CHECK(a.value() == Json::array());
    a.apply("Unavailable", "", "");
    CHECK(a.value().is_null());
}

TEST_CASE("live values: observations by DataItem id, SHDR values by Source, name or id") {
    LiveValues live;
    live.install(std::make_shared<const ReverseModel>(model()));
    CHECK(live.get("xs") == std::optional<Json>(Json(nullptr)));
    CHECK_FALSE(live.get("nope"));
    CHECK(live.apply(StreamObservation{"xs", 5, "AxisFeedrate", "1", false, ""}));
    CHECK(live.get("xs")->get<double>() == Approx(60));
    CHECK_FALSE(live.apply(StreamObservation{"other-device-item", 6, "Position", "1", false, ""}));
    CHECK(live.apply_condition("system", "Fault", "12", "Overheat"));
    CHECK(live.get("sys")->size() == 1);
    CHECK(live.apply_value("avail", "AVAILABLE"));
    CHECK(live.available() == std::optional<bool>(true));
    // A fixed item keeps the model's value: observations do not change it.
    CHECK(live.apply_value("limit", "1"));
    CHECK(live.get("limit")->is_null());
    live.all_unavailable();
    CHECK(live.get("xs")->is_null());
    CHECK(live.get("sys")->is_null());
}

TEST_CASE("SHDR lines are split, unquoted and trimmed as the protocol describes") {
    CHECK(shdr_fields("2024-01-01T00:00:00Z|Xact|12.5|mode|AUTOMATIC") ==
          std::vector<std::string>{"2024-01-01T00:00:00Z", "Xact", "12.5", "mode", "AUTOMATIC"});
    CHECK(shdr_fields("t|sys|fault|1001|HIGH||Spindle overload\r\n") ==
          std::vector<std::string>{"t", "sys", "fault", "1001", "HIGH", "", "Spindle overload"});
    CHECK(shdr_fields("t|msg|\"a \\| b \\\" c\"|x| y ") == std::vector<std::string>{"t", "msg", "a | b \" c", "x", "y"});
    CHECK(shdr_fields("t|k|") == std::vector<std::string>{"t", "k", ""});
    CHECK(shdr_fields("t|k|\"open") == std::vector<std::string>{"t", "k", "\"open"});
    CHECK(shdr_pong_ms("* PONG 10000") == 10000);
    CHECK(shdr_pong_ms("* PONG 250\r") == 250);
    CHECK(shdr_pong_ms("* PONG") == -1);
    CHECK(shdr_pong_ms("* PONG x") == -1);
    CHECK(shdr_pong_ms("* PING") == -1);
    CHECK(shdr_split_key("mill:Xact") == std::pair<std::string, std::string>{"mill", "Xact"});
    CHECK(shdr_split_key("Xact") == std::pair<std::string, std::string>{"", "Xact"});
}
