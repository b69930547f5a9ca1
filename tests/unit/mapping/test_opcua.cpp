// map_to_opcua and opcua_mapping: namespaces, NodeIds, variable types,
// access levels, properties, fallbacks, and the OPC 40502 profile.
#include "mapping_test_util.hpp"

#include <catch2/catch.hpp>

#include <set>
#include <sstream>

#include <regex>

using namespace nclink;
using nclink::test::contains;
using nclink::test::fixed_options;
using nclink::test::load_mapping_model;
using nclink::test::parse_mapping_model;

namespace {

/// The <UAVariable ...> or <UAObject ...> start tag of a node.
std::string start_tag(const std::string& xml, const std::string& node_id) {
    const std::string key = "NodeId=\"" + node_id + "\"";
    const auto at = xml.find(key);
    if (at == std::string::npos) return {};
    const auto begin = xml.rfind('<', at);
    return xml.substr(begin, xml.find('>', at) - begin + 1);
}

/// The whole element of a node.
std::string element(const std::string& xml, const std::string& node_id) {
    const std::string tag = start_tag(xml, node_id);
    if (tag.empty()) return {};
    const auto begin = xml.find(tag);
    const std::string name = tag.substr(1, tag.find(' ') - 1);
    if (tag.size() >= 2 && tag[tag.size() - 2] == '/') return tag;
    return xml.substr(begin, xml.find("</" + name + ">", begin) - begin);
}

}  // namespace

TEST_CASE("one namespace per device with the device object organized under Objects") {
    auto doc = map_to_opcua(*load_mapping_model("sim-mill.json"), fixed_options());
    REQUIRE(doc.ok());
    CHECK(contains(doc->xml, "<Uri>urn:nclink:device:nclink-sim-mill-01</Uri>"));
    CHECK_FALSE(contains(doc->xml, "http://opcfoundation.org/UA/CNC"));
    const std::string device = element(doc->xml, "ns=1;s=nclink-sim-mill-01");
    REQUIRE_FALSE(device.empty());
    CHECK(contains(device, R"(<Reference ReferenceType="Organizes" IsForward="false">i=85</Reference>)"));
    CHECK(contains(device, R"(<Reference ReferenceType="HasTypeDefinition">ns=1;i=1001</Reference>)"));
    // Table B.1 mandatory children.
    CHECK(contains(device, "ns=1;s=nclink-sim-mill-01.Availability"));
    CHECK(contains(device, "ns=1;s=nclink-sim-mill-01.DataItems"));
    CHECK(contains(device, "ns=1;s=nclink-sim-mill-01.Components"));
    CHECK(contains(element(doc->xml, "ns=1;s=nclink-sim-mill-01.Manufacturer"), "<uax:String>nclink</uax:String>"));
    CHECK(contains(doc->xml, R"(<UAObjectType NodeId="ns=1;i=1001" BrowseName="1:DeviceType">)"));
    CHECK(contains(doc->xml, R"(BrowseName="1:ControllerType")"));

    auto m = opcua_mapping(*load_mapping_model("sim-mill.json"), fixed_options());
    REQUIRE(m.ok());
    REQUIRE(m->namespaces().size() == 1);
    CHECK(m->namespaces()[0].uri == "urn:nclink:device:nclink-sim-mill-01");
    CHECK(m->namespaces()[0].dev_uuid == "nclink-sim-mill-01");
}

TEST_CASE("every data object is a variable s=<NC-Link id> and every component an object") {
    const auto model = load_mapping_model("sim-mill.json");
    auto doc = map_to_opcua(*model, fixed_options());
    auto m = opcua_mapping(*model, fixed_options());
    REQUIRE(doc.ok());
    REQUIRE(m.ok());
    std::size_t data_objects = 0;
    for (const auto& d : model->data_objects()) {
        if (d.device_id.empty()) continue;
        ++data_objects;
        INFO(d.id);
        const UaVariable* v = m->find(d.id);
        REQUIRE(v != nullptr);
        CHECK(v->node_id == "ns=1;s=" + d.id);
        const std::string tag = start_tag(doc->xml, v->node_id);
        CHECK(contains(tag, "<UAVariable"));
        // Setable items: CurrentRead|CurrentWrite (3), others CurrentRead (1, the default).
        CHECK(v->access_level == (d.setable ? 3 : 1));
        CHECK(contains(tag, "AccessLevel=\"3\"") == d.setable);
        CHECK(contains(element(doc->xml, v->node_id), "<nclink:Item xmlns:nclink=\"urn:nclink:mapping\" id=\"" + d.id + "\""));
    }
    CHECK(m->variables().size() == data_objects);
    for (const auto& c : model->components()) CHECK(contains(start_tag(doc->xml, "ns=1;s=" + c.id), "<UAObject"));
    CHECK(contains(element(doc->xml, "ns=1;s=axis_x"), ">ns=1;i=1004</Reference>"));      // AxesType
    CHECK(contains(element(doc->xml, "ns=1;s=controller"), ">ns=1;i=1003</Reference>"));  // ControllerType
}

TEST_CASE("samples are AnalogItemType with UNECE EngineeringUnits and an EURange") {
    const auto model = load_mapping_model("sim-mill.json");
    auto doc = map_to_opcua(*model, fixed_options());
    auto m = opcua_mapping(*model, fixed_options());
    const UaVariable* x = m->find("x_position");
    CHECK(x->type_definition == "AnalogItemType");
    CHECK(x->data_type == "Double");
    CHECK(x->minimum_sampling_interval == 1);
    CHECK(contains(start_tag(doc->xml, "ns=1;s=x_position"), R"(MinimumSamplingInterval="1")"));
    const std::string eu = element(doc->xml, "ns=1;s=x_position.EngineeringUnits");
    CHECK(contains(eu, "<uax:Identifier>i=888</uax:Identifier>"));
    CHECK(contains(eu, "<uax:NamespaceUri>http://www.opcfoundation.org/UA/units/un/cefact</uax:NamespaceUri>"));
    CHECK(contains(eu, "<uax:UnitId>5066068</uax:UnitId>"));
    CHECK(contains(eu, "<uax:Text>mm</uax:Text>"));
    CHECK_FALSE(element(doc->xml, "ns=1;s=x_position.EURange").empty());
    // The OPC UA value is the NC-Link value: EngineeringUnits is the item's own unit.
    CHECK(contains(element(doc->xml, "ns=1;s=x_speed.EngineeringUnits"), "<uax:UnitId>4732977</uax:UnitId>"));
    CHECK(contains(element(doc->xml, "ns=1;s=spindle_override.EngineeringUnits"), "<uax:UnitId>20529</uax:UnitId>"));
}

TEST_CASE("EURange carries a value where the quantity has one") {
    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","version":"1.0.0","guid":"g",
        "dataItems":[{"id":"pf","type":"POWER_FACTOR"}]}]})");
    auto doc = map_to_opcua(*model, fixed_options());
    const std::string range = element(doc->xml, "ns=1;s=pf.EURange");
    CHECK(contains(range, "<uax:Identifier>i=885</uax:Identifier>"));
    CHECK(contains(range, "<uax:Low>-1</uax:Low>"));
    CHECK(contains(range, "<uax:High>1</uax:High>"));
}

TEST_CASE("every variable a SAMPLE_CHANNEL lists carries SampleInterval in ms (table B.7), no other") {
    const auto model = load_mapping_model("sim-mill.json");
    for (const auto profile : {OpcUaProfile::basic, OpcUaProfile::cnc}) {
        auto doc = map_to_opcua(*model, fixed_options(profile));
        auto m = opcua_mapping(*model, fixed_options(profile));
        REQUIRE(doc.ok());
        REQUIRE(m.ok());
        std::size_t sampled = 0;
        for (const auto& v : m->variables()) {
            INFO(v.item_id);
            const std::string property = element(doc->xml, v.node_id + ".SampleInterval");
            if (v.minimum_sampling_interval > 0) {
                ++sampled;
                CHECK(contains(start_tag(doc->xml, v.node_id + ".SampleInterval"), R"(DataType="Duration")"));
                CHECK(contains(start_tag(doc->xml, v.node_id + ".SampleInterval"), R"(BrowseName="1:SampleInterval")"));
                std::ostringstream ms;
                ms << v.minimum_sampling_interval;
                CHECK(contains(property, "<uax:Double>" + ms.str() + "</uax:Double>"));
                CHECK(contains(start_tag(doc->xml, v.node_id + ".SampleInterval"), "ParentNodeId=\"" + v.node_id + "\""));
            } else {
                CHECK(property.empty());
            }
        }
        CHECK(sampled >= 10);  // the mill's two channels
    }
    // x_position is in the 1 ms channel.
    auto doc = map_to_opcua(*model, fixed_options());
    CHECK(contains(element(doc->xml, "ns=1;s=x_position.SampleInterval"), "<uax:Double>1</uax:Double>"));
}

TEST_CASE("every AnalogItem has an EURange value: the model's limits, else the quantity's, else a default") {
    // The mill: every analog variable (positions, speeds, loads, currents,
    // overrides, feed) has Low and High.
    const auto mill = load_mapping_model("sim-mill.json");
    for (const auto profile : {OpcUaProfile::basic, OpcUaProfile::cnc}) {
        auto doc = map_to_opcua(*mill, fixed_options(profile));
        REQUIRE(doc.ok());
        std::size_t analog = 0;
        std::regex range_element(R"re(<UAVariable NodeId="([^"]*\.EURange)")re");
        for (auto it = std::sregex_iterator(doc->xml.begin(), doc->xml.end(), range_element); it != std::sregex_iterator(); ++it) {
            INFO((*it)[1]);
            const std::string range = element(doc->xml, (*it)[1]);
            CHECK(contains(range, "<uax:Low>"));
            CHECK(contains(range, "<uax:High>"));
            ++analog;
        }
        CHECK(analog >= 17);
    }
    auto doc = map_to_opcua(*mill, fixed_options());
    // Defaults, in the item's unit: length +-10000 mm, percent 0..200, r/min +-100000, A +-1000.
    CHECK(contains(element(doc->xml, "ns=1;s=x_position.EURange"), "<uax:Low>-10000</uax:Low>"));
    CHECK(contains(element(doc->xml, "ns=1;s=x_position.EURange"), "<uax:High>10000</uax:High>"));
    CHECK(contains(element(doc->xml, "ns=1;s=spindle_override.EURange"), "<uax:Low>0</uax:Low>"));
    CHECK(contains(element(doc->xml, "ns=1;s=spindle_override.EURange"), "<uax:High>200</uax:High>"));
    CHECK(contains(element(doc->xml, "ns=1;s=x_current.EURange"), "<uax:High>1000</uax:High>"));

    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","version":"1.0.0","guid":"g","components":[
        {"id":"ax","type":"AXIS","number":"X","dataItems":[
          {"id":"x","type":"POSITION","units":"mm","minimum":-500,"maximum":850},
          {"id":"xm","type":"POSITION","units":"m"},
          {"id":"xh","type":"POSITION","units":"mm","maximum":900}]},
        {"id":"sp","type":"AXIS","number":"S",
         "configs":[{"id":"smax","type":"UPPER_LIMIT","value":12000,"units":"r/min"},
                    {"id":"nolimit","type":"UPPER_LIMIT","value":7}],
         "dataItems":[{"id":"s","type":"SPINDLE_SPEED","units":"r/min"},
                      {"id":"l","type":"AXIS_LOAD","units":"PERCENT"}]}]}]})");
    REQUIRE(model);
    doc = map_to_opcua(*model, fixed_options());
    REQUIRE(doc.ok());
    const auto range = [&](const char* id) { return element(doc->xml, std::string("ns=1;s=") + id + ".EURange"); };
    // The item's own minimum/maximum (GB/T 39561.3 LValue/HValue).
    CHECK(contains(range("x"), "<uax:Low>-500</uax:Low>"));
    CHECK(contains(range("x"), "<uax:High>850</uax:High>"));
    // Only a maximum: the low end from the default.
    CHECK(contains(range("xh"), "<uax:Low>-10000</uax:Low>"));
    CHECK(contains(range("xh"), "<uax:High>900</uax:High>"));
    // The default converted to the item's unit: 10000 mm is 10 m.
    CHECK(contains(range("xm"), "<uax:Low>-10</uax:Low>"));
    CHECK(contains(range("xm"), "<uax:High>10</uax:High>"));
    // An UPPER_LIMIT of the same quantity beside it bounds the spindle speed,
    // not the load (another quantity); the one without units bounds nothing.
    CHECK(contains(range("s"), "<uax:High>12000</uax:High>"));
    CHECK(contains(range("l"), "<uax:High>200</uax:High>"));
}

TEST_CASE("states are discrete types - two words TwoState and more MultiState with EnumStrings") {
    const auto model = load_mapping_model("sim-mill.json");
    auto doc = map_to_opcua(*model, fixed_options());
    auto m = opcua_mapping(*model, fixed_options());
    const UaVariable* emg = m->find("emergency_stop");
    CHECK(emg->type_definition == "TwoStateDiscreteType");
    CHECK(emg->data_type == "Boolean");
    CHECK(emg->encoding == UaEncoding::two_state);
    CHECK(contains(element(doc->xml, "ns=1;s=emergency_stop.TrueState"), "<uax:Text>triggered</uax:Text>"));

    const UaVariable* status = m->find("status");
    CHECK(status->type_definition == "MultiStateDiscreteType");
    CHECK(status->data_type == "UInt32");
    CHECK(status->encoding == UaEncoding::enum_index);
    CHECK(status->enum_strings == std::vector<std::string>{"running", "free", "holding"});
    const std::string strings = element(doc->xml, "ns=1;s=status.EnumStrings");
    CHECK(contains(strings, R"(ValueRank="1" ArrayDimensions="3")"));
    CHECK(contains(strings, "<uax:ListOfLocalizedText>"));

    const UaVariable* mode = m->find("work_mode");
    CHECK(mode->type_definition == "TwoStateDiscreteType");
    CHECK(mode->true_value == "auto");
    CHECK(mode->false_value == "manual");
}

TEST_CASE("lists and dicts and objects are Strings holding JSON") {
    const auto model = load_mapping_model("sim-mill.json");
    auto m = opcua_mapping(*model, fixed_options());
    for (const char* id : {"tools", "parameters", "coordinates", "warning"}) {
        INFO(id);
        CHECK(m->find(id)->data_type == "String");
        CHECK(m->find(id)->encoding == UaEncoding::json);
        CHECK(m->find(id)->type_definition == "DataItemType");
    }
}

TEST_CASE("fixed values go into the NodeSet in the variable's DataType") {
    const auto model = load_mapping_model("sim-mill.json");
    auto doc = map_to_opcua(*model, fixed_options());
    CHECK(contains(element(doc->xml, "ns=1;s=spindle_max_speed"), "<uax:Double>12000</uax:Double>"));
    CHECK(contains(element(doc->xml, "ns=1;s=machine_model"), "<uax:String>SIM-VMC-850</uax:String>"));
    CHECK(contains(element(doc->xml, "ns=1;s=serial_number"), "<uax:String>1</uax:String>"));
    // A fixed word is a String holding the word, not a discrete type's index
    // or flag: CATAGORY on the device (table 16 machine kinds) and on an axis.
    CHECK(contains(element(doc->xml, "ns=1;s=machine_category"), "<uax:String>milling</uax:String>"));
    CHECK(contains(element(doc->xml, "ns=1;s=x_category"), "<uax:String>linear</uax:String>"));
    auto m = opcua_mapping(*model, fixed_options());
    for (const char* id : {"machine_category", "x_category"}) {
        INFO(id);
        const UaVariable* v = m->find(id);
        REQUIRE(v);
        CHECK(v->data_type == "String");
        CHECK(v->encoding == UaEncoding::scalar);
        CHECK(v->type_definition == "DataItemType");
        CHECK(contains(start_tag(doc->xml, std::string("ns=1;s=") + id), R"(DataType="String")"));
        CHECK_FALSE(contains(doc->xml, std::string("ns=1;s=") + id + ".EnumStrings"));
        CHECK_FALSE(contains(doc->xml, std::string("ns=1;s=") + id + ".TrueState"));
    }
    // A word the model does not fix keeps its discrete type (work_mode, above).
    CHECK(m->find("work_mode")->encoding == UaEncoding::two_state);
}

TEST_CASE("unknown types fall back to BaseDataVariableType and are listed") {
    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "configs":[{"id":"root_cfg","type":"VERSION","value":"1"}],
      "devices":[{"id":"d","type":"MACHINE","version":"1.0.0","guid":"g",
        "dataItems":[{"id":"v1","type":"VIBRATION_X","value":[1,2]}],
        "components":[{"id":"t","type":"TURRET"}]}]})");
    auto doc = map_to_opcua(*model, fixed_options());
    REQUIRE(doc.ok());
    const std::string v1 = element(doc->xml, "ns=1;s=v1");
    CHECK(contains(v1, R"(DataType="BaseDataType" ValueRank="-2")"));
    CHECK(contains(v1, ">i=63</Reference>"));
    CHECK(contains(v1, "<uax:String>[1,2]</uax:String>"));
    std::set<std::string> ids;
    for (const auto& u : doc->unmapped) ids.insert(u.id);
    CHECK(ids == std::set<std::string>{"root_cfg", "v1", "t"});
    auto m = opcua_mapping(*model, fixed_options());
    CHECK(m->find("v1")->fallback);
}

TEST_CASE("two devices are two namespaces") {
    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[
        {"id":"a","type":"MACHINE","version":"1.0.0","guid":"ga","dataItems":[{"id":"a1","type":"EMG"}]},
        {"id":"b","type":"MACHINE","version":"1.0.0","guid":"gb","dataItems":[{"id":"b1","type":"EMG"}]}]})");
    auto m = opcua_mapping(*model, fixed_options());
    REQUIRE(m.ok());
    REQUIRE(m->namespaces().size() == 2);
    CHECK(m->namespaces()[1].uri == "urn:nclink:device:gb");
    CHECK(m->find("a1")->node_id == "ns=1;s=a1");
    CHECK(m->find("b1")->node_id == "ns=2;s=b1");
    CHECK(m->find("b1")->namespace_uri == "urn:nclink:device:gb");
}

TEST_CASE("an NC-Link id equal to a generated NodeId is an error and not a silent clash") {
    const auto model = parse_mapping_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","version":"1.0.0","guid":"g",
        "dataItems":[{"id":"x","type":"POSITION"},{"id":"x.EURange","type":"EMG"}]}]})");
    auto doc = map_to_opcua(*model, fixed_options());
    REQUIRE_FALSE(doc.ok());
    CHECK(doc.error().code == ErrorCode::key_error);
    CHECK(contains(doc.error().message, "x.EURange"));
}

TEST_CASE("cnc profile maps axes and spindles and controllers to OPC 40502 objects") {
    const auto model = load_mapping_model("sim-mill.json");
    const auto options = fixed_options(OpcUaProfile::cnc);
    auto doc = map_to_opcua(*model, options);
    auto m = opcua_mapping(*model, options);
    REQUIRE(doc.ok());
    REQUIRE(m.ok());
    REQUIRE(m->namespaces().size() == 2);
    CHECK(m->namespaces()[1].uri == "http://opcfoundation.org/UA/CNC");
    CHECK(contains(doc->xml, "<Uri>http://opcfoundation.org/UA/CNC</Uri>"));
    CHECK(contains(doc->xml, R"(<RequiredModel ModelUri="http://opcfoundation.org/UA/CNC" Version="1.0.0")"));

    const std::string iface = element(doc->xml, "ns=1;s=nclink-sim-mill-01.CncInterface");
    CHECK(contains(iface, ">ns=2;i=1007</Reference>"));  // CncInterfaceType
    CHECK(contains(element(doc->xml, "ns=1;s=nclink-sim-mill-01.CncInterface.VendorName"), "<uax:String>nclink</uax:String>"));
    CHECK(contains(element(doc->xml, "ns=1;s=nclink-sim-mill-01.CncInterface.VendorRevision"), "<uax:String>1.0.0</uax:String>"));

    // Axes keep their NodeId, take the CNC type and hang below CncAxisList.
    const std::string x = start_tag(doc->xml, "ns=1;s=axis_x");
    CHECK(contains(x, R"(ParentNodeId="ns=1;s=nclink-sim-mill-01.CncInterface.CncAxisList")"));
    CHECK(contains(element(doc->xml, "ns=1;s=axis_x"), ">ns=2;i=1004</Reference>"));
    CHECK(contains(start_tag(doc->xml, "ns=1;s=spindle"), "CncSpindleList"));
    CHECK(contains(start_tag(doc->xml, "ns=1;s=controller"), "CncChannelList"));
    CHECK(contains(element(doc->xml, "ns=1;s=controller.Id"), "<uax:UInt32>1</uax:UInt32>"));
    CHECK(contains(element(doc->xml, "ns=1;s=axis_x.IsRotational"), "<uax:Boolean>false</uax:Boolean>"));
    CHECK(contains(element(doc->xml, "ns=1;s=axis_x.ActChannel"), "<uax:Identifier>ns=1;s=controller</uax:Identifier>"));

    // Mandatory children filled from NC-Link items keep the item's NodeId.
    struct Slot {
        const char* item;
        const char* slot;
        const char* browse;
        const char* parent;
    };
    for (const Slot& s : {Slot{"x_position", "CncAxisType/PosDirect/ActPos", "2:ActPos", "ns=1;s=axis_x.PosDirect"},
                          Slot{"x_load", "CncAxisType/ActLoad", "2:ActLoad", "ns=1;s=axis_x"},
                          Slot{"spindle_speed", "CncSpindleType/ActSpeed", "2:ActSpeed", "ns=1;s=spindle"},
                          Slot{"spindle_override", "CncSpindleType/ActOverride", "2:ActOverride", "ns=1;s=spindle"},
                          Slot{"feed_speed", "CncChannelType/ActFeedrate", "2:ActFeedrate", "ns=1;s=controller"},
                          Slot{"program", "CncChannelType/ActMainProgramName", "2:ActMainProgramName", "ns=1;s=controller"},
                          Slot{"tool_number", "CncChannelType/ToolId", "2:ToolId", "ns=1;s=controller"}}) {
        INFO(s.item);
        const UaVariable* v = m->find(s.item);
        REQUIRE(v != nullptr);
        CHECK(v->cnc_slot == s.slot);
        CHECK(v->node_id == std::string("ns=1;s=") + s.item);
        const std::string tag = start_tag(doc->xml, v->node_id);
        CHECK(contains(tag, std::string("BrowseName=\"") + s.browse + "\""));
        CHECK(contains(tag, std::string("ParentNodeId=\"") + s.parent + "\""));
    }
    CHECK(m->find("tool_number")->data_type == "UInt32");
    // Slots no item fills are placeholders; items no slot takes stay as they are.
    CHECK(contains(element(doc->xml, "ns=1;s=axis_x.ActPower"), "OPC 40502 placeholder"));
    CHECK(contains(element(doc->xml, "ns=1;s=axis_x.PosDirect.CmdPos"), "OPC 40502 placeholder"));
    CHECK(m->find("x_current")->cnc_slot.empty());
    CHECK(m->find("status")->cnc_slot.empty());
}

TEST_CASE("cnc profile fills an axis slot from a component below the axis") {
    const auto model = load_mapping_model("appendix-b-corrected.json");
    auto m = opcua_mapping(*model, fixed_options(OpcUaProfile::cnc));
    REQUIRE(m.ok());
    // The X axis' position sits on its SCREW (appendix B of GB/T 41970).
    CHECK(m->find("0103080402")->cnc_slot == "CncAxisType/PosDirect/ActPos");
    // Device-level feed data fills the only channel.
    CHECK(m->find("010303")->cnc_slot == "CncChannelType/ActFeedrate");
    CHECK(m->find("010305")->cnc_slot == "CncChannelType/ActOverride");
    auto doc = map_to_opcua(*model, fixed_options(OpcUaProfile::cnc));
    CHECK(contains(element(doc->xml, "ns=1;s=010311.IsRotational"), "<uax:Boolean>true</uax:Boolean>"));
    // The screw still organizes the item it holds.
    CHECK(contains(element(doc->xml, "ns=1;s=01030804"), R"(<Reference ReferenceType="Organizes">ns=1;s=0103080402</Reference>)"));
}
