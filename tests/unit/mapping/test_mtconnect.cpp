// map_to_mtconnect and mtconnect_mapping: structure, ids, units, fallbacks.
#include "mapping_test_util.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace nclink;
using nclink::test::contains;
using nclink::test::fixed_options;
using nclink::test::load_mapping_model;
using nclink::test::parse_mapping_model;

namespace {

std::string one_device(const std::string& body) {
    return R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[{"id":"dev","type":"MACHINE","version":"1.0.0","guid":"dev-guid",)" +
           body + "}]}";
}

}  // namespace

TEST_CASE("the device uuid is the terminal id and AVAILABILITY comes first") {
    const auto model = load_mapping_model("sim-mill.json");
    auto doc = map_to_mtconnect(*model, fixed_options());
    REQUIRE(doc.ok());
    CHECK(contains(doc->xml, R"(<Device id="mill" name="Simulated_3-axis_mill" uuid="nclink-sim-mill-01">)"));
    CHECK(contains(doc->xml, R"(<DataItems>
        <DataItem category="EVENT" id="mill_avail" name="avail" type="AVAILABILITY"/>)"));
    CHECK(contains(doc->xml, R"(creationTime="2024-01-01T00:00:00Z")"));
    // Table A.1 rows 3-5: fixed manufacturer, model, serial number.
    CHECK(contains(
        doc->xml,
        R"(<Description manufacturer="nclink" model="SIM-VMC-850" serialNumber="1">VMC-3Axis simulated by nclink</Description>)"));

    auto m = mtconnect_mapping(*model, fixed_options());
    REQUIRE(m.ok());
    REQUIRE(m->devices().size() == 1);
    CHECK(m->devices()[0].uuid == "nclink-sim-mill-01");
    CHECK(m->devices()[0].availability_id == "mill_avail");
    CHECK(m->device("nclink-sim-mill-01") == m->device("mill"));
    CHECK(m->find("manufacturer")->target == MtTarget::description_attribute);
    CHECK(m->find("manufacturer")->attribute == "manufacturer");
}

TEST_CASE("axes go into an Axes container as Linear or Rotary named by their number") {
    auto m = mtconnect_mapping(*load_mapping_model("sim-mill.json"), fixed_options());
    REQUIRE(m.ok());
    const MtDataItem* x = m->find("x_position");
    REQUIRE(x != nullptr);
    CHECK(x->id == "x_position");
    CHECK(x->category == MtCategory::sample);
    CHECK(x->type == "POSITION");
    CHECK(x->sub_type == "ACTUAL");
    CHECK(x->units == "MILLIMETER");
    CHECK(x->native_units.empty());
    CHECK(x->element == "Position");
    CHECK(x->component_id == "axis_x");
    CHECK(x->component_element == "Linear");
    CHECK(x->component_name == "X");
    CHECK(x->device_uuid == "nclink-sim-mill-01");
    REQUIRE(x->sample_rate.has_value());
    CHECK(*x->sample_rate == Approx(1000));  // sampleInterval 1 ms (A.4 h)
    // The X axis' CATAGORY "linear" chose the element (table A.2 row 3).
    CHECK(m->find("x_category")->target == MtTarget::component_element);

    // Axis S with spindle items is a spindle: Rotary (table A.2 row 2).
    const MtDataItem* s = m->find("spindle_speed");
    CHECK(s->component_element == "Rotary");
    CHECK(s->type == "ROTARY_VELOCITY");
    CHECK(s->units == "REVOLUTION/MINUTE");
    CHECK(*s->sample_rate == Approx(10));

    auto doc = map_to_mtconnect(*load_mapping_model("sim-mill.json"), fixed_options());
    CHECK(contains(doc->xml, R"(<Axes id="mill_axes">)"));
    CHECK(contains(doc->xml, R"(<Rotary id="spindle" name="S">)"));
}

TEST_CASE("a controller's process data goes to its Path while conditions stay on the Controller") {
    auto m = mtconnect_mapping(*load_mapping_model("sim-mill.json"), fixed_options());
    REQUIRE(m.ok());
    CHECK(m->find("status")->component_id == "controller_path");
    CHECK(m->find("status")->component_element == "Path");
    CHECK(m->find("status")->element == "Execution");
    CHECK(m->find("program")->component_id == "controller_path");
    CHECK(m->find("warning")->component_id == "controller");
    CHECK(m->find("warning")->component_element == "Controller");
    CHECK(m->find("emergency_stop")->component_element == "Device");
    CHECK(m->find("emergency_stop")->component_id == "mill");
}

TEST_CASE("units follow the item converted to MTConnect units with nativeUnits kept") {
    auto m = mtconnect_mapping(*load_mapping_model("sim-mill.json"), fixed_options());
    const MtDataItem* speed = m->find("x_speed");
    CHECK(speed->type == "AXIS_FEEDRATE");  // SPEED on an axis (A.5 0x212A)
    CHECK(speed->units == "MILLIMETER/SECOND");
    CHECK(speed->native_units == "MILLIMETER/MINUTE");
    CHECK(speed->scale == Approx(1.0 / 60));
    // Numeric events (overrides) are converted but carry no units.
    CHECK(m->find("feed_override")->units.empty());
    CHECK(m->find("feed_override")->category == MtCategory::event);
}

TEST_CASE("an angular unit turns a length type into an angle") {
    const auto model = parse_mapping_model(one_device(R"("components":[{"id":"c_axis","type":"AXIS","number":"C",
        "dataItems":[{"id":"c_pos","type":"POSITION","units":"rad"},
                     {"id":"c_speed","type":"SPEED","units":"RADIAN/SECOND"},
                     {"id":"c_rest","type":"RESIDUAL","units":"DEGREE"}]}])"));
    auto m = mtconnect_mapping(*model, fixed_options());
    REQUIRE(m.ok());
    CHECK(m->find("c_pos")->type == "ANGLE");
    CHECK(m->find("c_pos")->sub_type == "ACTUAL");
    CHECK(m->find("c_pos")->units == "DEGREE");
    CHECK(m->find("c_pos")->native_units == "RADIAN");
    CHECK(m->find("c_pos")->element == "Angle");
    CHECK(m->find("c_pos")->component_element == "Rotary");  // table 9: C is rotary
    CHECK(m->find("c_speed")->type == "ANGULAR_VELOCITY");
    CHECK(m->find("c_rest")->type == "ANGLE");
    CHECK(m->find("c_rest")->sub_type.empty());
}

TEST_CASE("a unit of another quantity is kept and noted") {
    const auto model = parse_mapping_model(one_device(R"("dataItems":[{"id":"load","type":"AXIS_LOAD"},
        {"id":"odd","type":"POSITION","units":"furlong"}])"));
    auto doc = map_to_mtconnect(*model, fixed_options());
    REQUIRE(doc.ok());
    auto m = mtconnect_mapping(*model, fixed_options());
    // Table 13 gives AXIS_LOAD in kg; MTConnect LOAD is a percentage.
    CHECK(m->find("load")->type == "LOAD");
    CHECK(m->find("load")->units == "KILOGRAM");
    CHECK(m->find("odd")->units == "MILLIMETER");
    bool load_noted = false, odd_noted = false;
    for (const auto& n : doc->notes) {
        load_noted |= n.id == "load" && contains(n.message, "KILOGRAM");
        odd_noted |= n.id == "odd" && contains(n.message, "furlong");
    }
    CHECK(load_noted);
    CHECK(odd_noted);
}

TEST_CASE("fallbacks are EVENT MESSAGE subType x:<TYPE> listed with a reason") {
    const auto model = load_mapping_model("sim-mill.json");
    auto doc = map_to_mtconnect(*model, fixed_options());
    REQUIRE(doc.ok());
    CHECK(contains(doc->xml, R"(<DataItem category="EVENT" id="tools" name="Tool_table" type="MESSAGE" subType="x:TOOL"/>)"));
    std::set<std::string> ids, not_written;
    for (const auto& u : doc->unmapped) {
        CHECK_FALSE(u.reason.empty());
        if (u.fallback == "not written") not_written.insert(u.id);
        else if (contains(u.fallback, "EVENT MESSAGE x:")) ids.insert(u.id);
        else FAIL("unexpected fallback " << u.fallback);
    }
    CHECK(ids ==
          std::set<std::string>{"machine_category", "spindle_max_speed", "cnc_version", "tools", "parameters", "coordinates"});
    // The root's METHOD objects have no place in either document: listed too.
    CHECK(not_written == std::set<std::string>{"cycle_start", "feed_hold", "reset", "program_transfer"});
    auto m = mtconnect_mapping(*model, fixed_options());
    CHECK(m->find("tools")->target == MtTarget::fallback);
    CHECK(m->find("tools")->element == "Message");
    // A.4 c): a fixed value is the constraint.
    CHECK(contains(doc->xml, "<Value>12000</Value>"));
}

TEST_CASE("unknown types and components are never dropped") {
    const auto model = parse_mapping_model(one_device(R"("dataItems":[{"id":"v1","type":"VIBRATION_X"}],
        "components":[{"id":"turret","type":"TURRET","dataItems":[{"id":"t1","type":"TURRET_POS"}]}])"));
    auto doc = map_to_mtconnect(*model, fixed_options());
    REQUIRE(doc.ok());
    CHECK(contains(doc->xml, R"(<System id="turret">)"));
    CHECK(contains(doc->xml, R"(id="v1" type="MESSAGE" subType="x:VIBRATION_X")"));
    CHECK(contains(doc->xml, R"(id="t1" type="MESSAGE" subType="x:TURRET_POS")"));
    std::set<std::string> ids;
    for (const auto& u : doc->unmapped) ids.insert(u.id);
    CHECK(ids == std::set<std::string>{"v1", "turret", "t1"});
}

TEST_CASE("a list or dict item of a typed quantity falls back to MESSAGE") {
    const auto model = parse_mapping_model(one_device(R"("dataItems":[{"id":"p","type":"POSITION","datatype":"list"},
                                   {"id":"prog","type":"PROGRAM","datatype":"dict"}])"));
    auto m = mtconnect_mapping(*model, fixed_options());
    REQUIRE(m.ok());
    CHECK(m->find("p")->target == MtTarget::fallback);
    CHECK(m->find("prog")->target == MtTarget::data_item);  // PROGRAM is free text
    CHECK(m->find("prog")->type == "PROGRAM");
}

TEST_CASE("ids that are no XML names are escaped and aliases read as chapter 7") {
    const auto model = load_mapping_model("appendix-b.json");
    auto doc = map_to_mtconnect(*model, fixed_options());
    REQUIRE(doc.ok());
    CHECK(contains(doc->xml, R"(<Device id="_0103" name="数控机床" uuid="0103">)"));
    auto m = mtconnect_mapping(*model, fixed_options());
    const MtDataItem* pos = m->find("0103080402");
    REQUIRE(pos != nullptr);
    CHECK(pos->id == "_0103080402");
    CHECK(nclink_id_from_mtconnect(pos->id) == std::optional<std::string>("0103080402"));
    CHECK(m->find_by_mtconnect_id("_0103080402") == pos);
    CHECK(pos->component_id == "_01030804");  // the SCREW, below the X axis
    CHECK(pos->component_element == "System");
    CHECK(m->devices()[0].availability_id == "_0103_avail");
    // SPDL_OVERRIDE is SPINDLE_OVERRIDE, TYPE is CATAGORY (conformance aliases).
    CHECK(m->find("010306")->type == "ROTARY_VELOCITY_OVERRIDE");
    CHECK(m->find("010306")->nclink_type == "SPINDLE_OVERRIDE");
    CHECK(m->find("01030803")->target == MtTarget::component_element);
    bool noted = false;
    for (const auto& n : doc->notes) noted |= n.id == "010306" && contains(n.message, "SPDL_OVERRIDE");
    CHECK(noted);
}

TEST_CASE("generated ids step around ids of the model") {
    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","version":"1.0.0","guid":"g",
        "dataItems":[{"id":"d_avail","type":"EMG"},{"id":"d_axes","type":"EMG"}],
        "components":[{"id":"x","type":"AXIS","number":"X"},
                      {"id":"cnc","type":"CONTROLLER","dataItems":[{"id":"cnc_path","type":"PROGRAM"},{"id":"p2","type":"PROGRAM"}]}]}]})");
    auto m = mtconnect_mapping(*model, fixed_options());
    REQUIRE(m.ok());
    CHECK(m->devices()[0].availability_id == "d_avail_");
    CHECK(m->find("p2")->component_id == "cnc_path_");
    auto doc = map_to_mtconnect(*model, fixed_options());
    CHECK(contains(doc->xml, R"(<Axes id="d_axes_">)"));
}

TEST_CASE("device selection and terminal id override") {
    const std::string two = R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[
        {"id":"a","type":"MACHINE","version":"1.0.0","guid":"guid-a","dataItems":[{"id":"a1","type":"EMG"}]},
        {"id":"b","type":"MACHINE","version":"1.0.0","dataItems":[{"id":"b1","type":"EMG"}]}]})";
    const auto model = parse_mapping_model(two);
    auto both = mtconnect_mapping(*model, fixed_options());
    REQUIRE(both.ok());
    CHECK(both->devices().size() == 2);
    CHECK(both->devices()[1].uuid == "b");  // no guid: the id (resolve_dev_uuid)

    MappingOptions o = fixed_options();
    o.device = "guid-a";
    o.dev_uuid = "override-1";
    auto one = mtconnect_mapping(*model, o);
    REQUIRE(one.ok());
    REQUIRE(one->devices().size() == 1);
    CHECK(one->devices()[0].uuid == "override-1");
    CHECK(one->find("b1") == nullptr);
    CHECK(one->find("a1")->device_uuid == "override-1");

    o.device = "nope";
    auto missing = map_to_mtconnect(*model, o);
    REQUIRE_FALSE(missing.ok());
    CHECK(missing.error().code == ErrorCode::node_not_exists);

    o.device.clear();
    auto ambiguous = map_to_opcua(*model, o);
    REQUIRE_FALSE(ambiguous.ok());
    CHECK(ambiguous.error().code == ErrorCode::arguments_nimiety);
}

TEST_CASE("attribute text is escaped in the document") {
    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","version":"1.0.0","guid":"g<&>\"'",
        "description":"a < b & c > d \"q\" 'a'\nline",
        "dataItems":[{"id":"x","name":"A&B","type":"EMG"}]}]})");
    auto doc = map_to_mtconnect(*model, fixed_options());
    REQUIRE(doc.ok());
    CHECK(contains(doc->xml, R"(uuid="g&lt;&amp;&gt;&quot;&apos;")"));
    CHECK(contains(doc->xml, "a &lt; b &amp; c &gt; d &quot;q&quot; &apos;a&apos;&#10;line"));
    CHECK(contains(doc->xml, R"(name="A_B")"));  // NMTOKEN form
}
