// Real consumers: every document the mapping writes is checked by xmllint
// against the MTConnect 1.4 and OPC UA NodeSet schemas, Streams documents
// built from the lookup against the Streams schema, and the NodeSets are
// loaded into node-opcua. Each check skips with a message when its tool or
// the shared interop fixtures are missing (CI has them).
#include "mapping_test_util.hpp"

#include "mapping/mapping_table.hpp"

#include <catch2/catch.hpp>

#include <map>

using namespace nclink;
using namespace nclink::test;

namespace {

// GB/T 41970-2022 tables 10, 12, 13 and table 8 (plus types of no table).
const char* const kDataTypes[] = {"ACCELERATION",
                                  "ANGLE",
                                  "ANGULAR_ACCELERATION",
                                  "ANGULAR_VELOCITY",
                                  "CONCENTRATION",
                                  "CONDUCTIVITY",
                                  "CURRENT",
                                  "DISPLACEMENT",
                                  "ENERGY",
                                  "FLOW",
                                  "FREQUENCY",
                                  "LENGTH",
                                  "MASS",
                                  "PERIOD",
                                  "POSITION",
                                  "POWER",
                                  "POWER_FACTOR",
                                  "PRESSURE",
                                  "RESISTANCE",
                                  "ROTATION_SPEED",
                                  "SPEED",
                                  "TEMPERATURE",
                                  "TORQUE",
                                  "VISCOSITY",
                                  "VOLT_AMPERE",
                                  "CATAGORY",
                                  "CREATE_TIME",
                                  "CREATOR",
                                  "IP",
                                  "MANUFACTURER",
                                  "MODEL",
                                  "NAME",
                                  "PARAMETER",
                                  "SERIAL_NUMBER",
                                  "STATUS",
                                  "UPPER_LIMIT",
                                  "USER_ROLE",
                                  "VARIABLE",
                                  "VERSION",
                                  "WARNING",
                                  "WORK_MODE",
                                  "AUTO_MODE",
                                  "AXIS_BACKLASH",
                                  "AXIS_LOAD",
                                  "AXIS_TOREFPOINT",
                                  "BLOCK_SKIP_MODE",
                                  "CHIP_REMOVAL",
                                  "COMPACITY",
                                  "CONSOLE",
                                  "COOLANT_ON",
                                  "COORDINATE",
                                  "CYCLE_START",
                                  "DOOR_CLOSED",
                                  "EDIT_MODE",
                                  "EMG",
                                  "FEED_HOLD",
                                  "FEED_OVERRIDE",
                                  "FEED_SPEED",
                                  "FILE",
                                  "FIXTURE_MODE",
                                  "HANDLE_MODE",
                                  "INCREMENTAL_MODE",
                                  "JOG_MODE",
                                  "LIGHTING_ON",
                                  "LINE_NUMBER",
                                  "LUBRICANT_ON",
                                  "MACHINE_LOCKED",
                                  "MDI_MODE",
                                  "MST_LOCKED",
                                  "OPT_STOP_MODE",
                                  "PATH_LEFT_LENGTH",
                                  "PART",
                                  "PART_COUNT",
                                  "PROGRAM",
                                  "PROGRAM_MODE",
                                  "PROGRAM_NUMBER",
                                  "RAPID_OVERRIDE",
                                  "REF_MODE",
                                  "RESET_MODE",
                                  "RESIDUAL",
                                  "SHELF_UNIT",
                                  "SINGLE_BLOCK_MODE",
                                  "SITE",
                                  "SPINDLE_MODE",
                                  "SPINDLE_OVERRIDE",
                                  "SPINDLE_SPEED",
                                  "SUBPROGRAM",
                                  "TOOL",
                                  "TOOL_CHANGE",
                                  "TOOL_CHANGING",
                                  "TOOL_PARAM",
                                  "TOOL_NUMBER",
                                  "TOOL_POSITION",
                                  "RATE",
                                  "VENDOR_SPECIFIC"};

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

/// A value of the type's JSON form (tables 10, 12, 13; words of tables 15, 16).
Json sample_value(const std::string& type, const mapping_detail::Placement& where) {
    using mapping_detail::ValueType;
    const auto* row = mapping_detail::find_data_row(type, where);
    if (row == nullptr) return "vendor";
    if (row->enum_count > 0) return std::string(row->enum_strings[0]);
    if (row->value_count > 0 && row->value_type == ValueType::string) return std::string(row->values[0].nclink);
    switch (row->value_type) {
        case ValueType::number: return 1.5;
        case ValueType::integer: return 3;
        case ValueType::boolean: return true;
        case ValueType::object: return Json{{"number", 7}, {"text", "alarm <7> & more"}};
        case ValueType::list: return Json::array({1, "two"});
        case ValueType::dict: return Json{{"k", "v"}};
        case ValueType::file:
        case ValueType::string:
        case ValueType::any: break;
    }
    if (type == "PART_COUNT" || type == "LINE_NUMBER") return "12";
    return "text with <markup> & \"quotes\"";
}

Json items(const std::string& prefix, bool with_values, const mapping_detail::Placement& where) {
    Json out = Json::array();
    for (const char* type : kDataTypes) {
        Json item = {{"id", prefix + lower(type)}, {"name", std::string(type) + " item"}, {"type", type}};
        if (with_values) item["value"] = sample_value(type, where);
        out.push_back(item);
    }
    return out;
}

/// One device with every data type on the device (with fixed values), on an
/// axis, below an axis, on a spindle and on a controller, and every
/// component type of table 8 plus one of no table.
std::string all_types_model() {
    using mapping_detail::Placement;
    Placement device, controller, axis, below;
    device.on_device = true;
    controller.on_controller = true;
    axis.on_axis = true;
    below.in_axis = true;
    Json others = Json::array();
    for (const char* type :
         {"AUXILIARY", "COMPONENT", "FIXTURE", "MOTOR", "SCREW", "SENSOR", "SERVO_DRIVER", "TOOL_MAGAZINE", "TURRET"})
        others.push_back({{"id", "c_" + lower(type)},
                          {"type", type},
                          {"dataItems", {{{"id", "c_" + lower(type) + "_status"}, {"type", "STATUS"}}}}});
    Json components = {
        {{"id", "ax_x"},
         {"type", "AXIS"},
         {"number", "X"},
         {"dataItems", items("x_", false, axis)},
         {"components", {{{"id", "ax_x_screw"}, {"type", "SCREW"}, {"dataItems", items("xs_", false, below)}}}}},
        {{"id", "ax_a"},
         {"type", "AXIS"},
         {"number", "A"},
         {"configs", {{{"id", "ax_a_kind"}, {"type", "CATAGORY"}, {"value", "rotary"}}}},
         {"dataItems", {{{"id", "a_pos"}, {"type", "POSITION"}, {"units", "DEGREE"}}}}},
        {{"id", "ax_s"},
         {"type", "AXIS"},
         {"number", "S"},
         {"dataItems",
          {{{"id", "s_speed"}, {"type", "SPINDLE_SPEED"}}, {{"id", "s_over"}, {"type", "SPINDLE_OVERRIDE"}, {"setable", true}}}}},
        {{"id", "cnc"},
         {"type", "CONTROLLER"},
         {"dataItems", items("n_", false, controller)},
         {"configs",
          {{{"id", "n_list"}, {"type", "VARIABLE"}, {"datatype", "list"}, {"setable", true}},
           {{"id", "n_dict"}, {"type", "PARAMETER"}, {"datatype", "dict"}}}}}};
    for (auto& c : others) components.push_back(c);
    Json model = {{"id", "root"},
                  {"type", "NC_LINK_ROOT"},
                  {"version", "1.0.0"},
                  {"devices",
                   {{{"id", "all"},
                     {"name", "All types"},
                     {"type", "MACHINE"},
                     {"version", "1.0.0"},
                     {"guid", "all-guid"},
                     {"description", "every type <of> chapter 7 & table 8"},
                     {"configs",
                      {{{"id", "ch"},
                        {"type", "SAMPLE_CHANNEL"},
                        {"sampleInterval", 5},
                        {"uploadInterval", 50},
                        {"ids", {{{"id", "x_position"}}, {{"id", "n_status"}}}}}}},
                     {"dataItems", items("d_", true, device)},
                     {"components", components}}}}};
    return model.dump(2);
}

struct Case {
    std::string name;
    std::shared_ptr<const Model> model;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    for (const char* name : {"sim-mill.json", "appendix-b.json", "appendix-b-corrected.json"})
        out.push_back({name, load_mapping_model(name)});
    out.push_back({"all-types", parse_mapping_model(all_types_model())});
    return out;
}

bool tools_ready(const std::string& dir) {
    if (dir.empty()) {
        WARN("SKIPPED: shared interop fixtures not found (<source>/../shared/interop or NCLINK_INTEROP_DIR)");
        return false;
    }
    if (!have_program("xmllint")) {
        WARN("SKIPPED: xmllint not installed (Debian package libxml2-utils)");
        return false;
    }
    return true;
}

std::string file_name(const std::string& model, const std::string& kind) {
    std::string base = model;
    if (const auto dot = base.find(".json"); dot != std::string::npos) base.erase(dot);
    return base + "." + kind + ".xml";
}

}  // namespace

TEST_CASE("the all-types model covers every type and loads") {
    const auto model = parse_mapping_model(all_types_model());
    auto doc = map_to_mtconnect(*model, fixed_options());
    REQUIRE(doc.ok());
    // Fallbacks are listed; each chapter-7 type maps somewhere.
    CHECK_FALSE(doc->unmapped.empty());
    auto m = mtconnect_mapping(*model, fixed_options());
    REQUIRE(m.ok());
    CHECK(m->items().size() == model->data_objects().size());
}

TEST_CASE("Devices documents validate against MTConnectDevices_1.4") {
    const std::string dir = interop_dir();
    if (!tools_ready(dir)) return;
    const std::string xsd = dir + "/mtconnect-schema/MTConnectDevices_1.4_1.0.xsd";
    for (const auto& c : cases()) {
        INFO(c.name);
        auto doc = map_to_mtconnect(*c.model, fixed_options());
        REQUIRE(doc.ok());
        const auto run = xmllint_schema(xsd, write_scratch(file_name(c.name, "devices"), doc->xml));
        INFO(run.output);
        CHECK(run.status == 0);
    }
}

TEST_CASE("NodeSet2 documents of both profiles validate against UANodeSet with Types") {
    const std::string dir = interop_dir();
    if (!tools_ready(dir)) return;
    const std::string xsd = dir + "/opcua-schema/UANodeSet-with-Types.xsd";
    for (const auto& c : cases())
        for (const auto profile : {OpcUaProfile::basic, OpcUaProfile::cnc}) {
            INFO(c.name << " " << to_string(profile));
            auto doc = map_to_opcua(*c.model, fixed_options(profile));
            REQUIRE(doc.ok());
            const std::string file = file_name(c.name, std::string(to_string(profile)) + ".NodeSet2");
            const auto run = xmllint_schema(xsd, write_scratch(file, doc->xml));
            INFO(run.output);
            CHECK(run.status == 0);
        }
}

TEST_CASE("Streams documents built from the lookup validate against MTConnectStreams_1.4") {
    const std::string dir = interop_dir();
    if (!tools_ready(dir)) return;
    const std::string xsd = dir + "/mtconnect-schema/MTConnectStreams_1.4_1.0.xsd";
    for (const auto& c : cases()) {
        INFO(c.name);
        auto m = mtconnect_mapping(*c.model, fixed_options());
        REQUIRE(m.ok());
        // Observations per component, in a document an agent could send.
        std::map<std::string, std::vector<std::string>> samples, events, conditions;
        std::map<std::string, std::pair<std::string, std::string>> components;
        std::map<std::string, std::string> device_of;
        int sequence = 1;
        for (const auto& item : m->items()) {
            if (item.target != MtTarget::data_item && item.target != MtTarget::fallback) continue;
            const DataObject* d = c.model->data_object(item.item_id);
            mapping_detail::Placement anywhere;
            const Json value = d->value ? *d->value : sample_value(item.nclink_type, anywhere);
            components[item.component_id] = {item.component_element, item.component_name};
            device_of[item.component_id] = item.device_uuid;
            for (const auto& o : mtconnect_observations(item, value)) {
                std::string xml = "<" + o.element + " dataItemId=\"" + xml_escape(item.id) + "\" sequence=\"" +
                                  std::to_string(sequence++) + "\" timestamp=\"2024-01-01T00:00:00Z\"";
                if (!item.sub_type.empty()) xml += " subType=\"" + xml_escape(item.sub_type) + "\"";
                if (item.category == MtCategory::condition) {
                    xml += " type=\"" + item.type + "\"";
                    if (!o.native_code.empty()) xml += " nativeCode=\"" + xml_escape(o.native_code) + "\"";
                }
                xml += ">" + xml_escape(o.value) + "</" + o.element + ">";
                auto& bucket = item.category == MtCategory::sample  ? samples
                               : item.category == MtCategory::event ? events
                                                                    : conditions;
                bucket[item.component_id].push_back(xml);
            }
        }
        std::string doc = R"(<?xml version="1.0" encoding="UTF-8"?>
<MTConnectStreams xmlns="urn:mtconnect.org:MTConnectStreams:1.4">
<Header creationTime="2024-01-01T00:00:00Z" sender="test" instanceId="1" version="1.4.0" bufferSize="131072" nextSequence=")" +
                          std::to_string(sequence) + R"(" firstSequence="1" lastSequence=")" + std::to_string(sequence - 1) + R"("/>
<Streams>
)";
        for (const auto& device : m->devices()) {
            doc += "<DeviceStream name=\"" + xml_escape(device.name) + "\" uuid=\"" + xml_escape(device.uuid) + "\">\n";
            doc += "<ComponentStream component=\"Device\" name=\"" + xml_escape(device.name) + "\" componentId=\"" + device.id +
                   "\">";
            if (!samples[device.id].empty()) {
                doc += "<Samples>";
                for (const auto& s : samples[device.id]) doc += s;
                doc += "</Samples>";
            }
            doc += "<Events><Availability dataItemId=\"" + device.availability_id + "\" sequence=\"" + std::to_string(sequence) +
                   "\" timestamp=\"2024-01-01T00:00:00Z\">AVAILABLE</Availability>";
            for (const auto& e : events[device.id]) doc += e;
            doc += "</Events>";
            if (!conditions[device.id].empty()) {
                doc += "<Condition>";
                for (const auto& s : conditions[device.id]) doc += s;
                doc += "</Condition>";
            }
            doc += "</ComponentStream>\n";
            for (const auto& [id, what] : components) {
                if (id == device.id || device_of[id] != device.uuid) continue;
                doc += "<ComponentStream component=\"" + what.first + "\"" +
                       (what.second.empty() ? "" : " name=\"" + xml_escape(what.second) + "\"") + " componentId=\"" + id + "\">";
                for (const auto& [tag, bucket] : {std::pair<const char*, decltype(&samples)>{"Samples", &samples},
                                                  {"Events", &events},
                                                  {"Condition", &conditions}}) {
                    const auto& list = (*bucket)[id];
                    if (list.empty()) continue;
                    doc += std::string("<") + tag + ">";
                    for (const auto& s : list) doc += s;
                    doc += std::string("</") + tag + ">";
                }
                doc += "</ComponentStream>\n";
            }
            doc += "</DeviceStream>\n";
        }
        doc += "</Streams>\n</MTConnectStreams>\n";
        const auto run = xmllint_schema(xsd, write_scratch(file_name(c.name, "streams"), doc));
        INFO(run.output);
        CHECK(run.status == 0);
    }
}

TEST_CASE("escaped text reads back unchanged through a real XML parser") {
    if (!have_program("xmllint")) {
        WARN("SKIPPED: xmllint not installed (Debian package libxml2-utils)");
        return;
    }
    const std::string nasty = "a < b & c > d \"q\" 'a'\tT\nL\r\nCR 数控 ✓";
    Json model = {{"id", "r"},
                  {"type", "NC_LINK_ROOT"},
                  {"version", "1.0.0"},
                  {"devices", {{{"id", "d"}, {"type", "MACHINE"}, {"version", "1.0.0"}, {"guid", nasty}, {"description", nasty}}}}};
    auto doc = map_to_mtconnect(*parse_mapping_model(model.dump()), fixed_options());
    REQUIRE(doc.ok());
    const std::string file = write_scratch("escaping.devices.xml", doc->xml);
    const auto description = run_command("xmllint --nonet --xpath 'string(//*[local-name()=\"Description\"])' '" + file + "'");
    // xmllint ends its output with a newline of its own.
    CHECK(description.status == 0);
    CHECK(description.output == nasty + "\n");
    const auto uuid = run_command("xmllint --nonet --xpath 'string(//*[local-name()=\"Device\"]/@uuid)' '" + file + "'");
    CHECK(uuid.output == nasty + "\n");
}

TEST_CASE("node-opcua loads the basic NodeSets alone and the cnc ones after the companion nodesets") {
    const std::string dir = interop_dir();
    const std::string modules = node_modules_dir();
    if (dir.empty() || modules.empty() || !have_program("node")) {
        WARN(
            "SKIPPED: node-opcua not installed (npm ci in tools/nclink-opcua), node missing or "
            "shared interop fixtures not found");
        return;
    }
    const std::string check = dir + "/tools/opcua-load-check.js";
    // OPC 40502 needs only the base nodeset; the MachineTool chain is loaded
    // too so the document must coexist with the companions a server offers.
    std::string chain;
    for (const char* file : {"Opc.Ua.Di.NodeSet2.xml", "Opc.Ua.IA.NodeSet2.xml", "Opc.Ua.Machinery.NodeSet2.xml",
                             "opc.ua.isa95-jobcontrol.nodeset2.xml", "Opc.Ua.Machinery.Jobs.Nodeset2.xml",
                             "Opc.Ua.MachineTool.NodeSet2.xml", "Opc.Ua.CNC.NodeSet.xml"})
        chain += "'" + dir + "/opcua-nodesets/" + file + "' ";
    const std::string cnc_only = "'" + modules + "/node-opcua-nodesets/nodesets/Opc.Ua.CNC.NodeSet.xml' ";
    const auto load = [&](const std::string& dependencies, const std::string& file) {
        const auto run = run_command("NODE_PATH='" + modules + "' node '" + check + "' " + dependencies + "'" + file + "'");
        INFO(run.output);
        CHECK(run.status == 0);
        CHECK_FALSE(contains(run.output, "DANGLING"));
        CHECK_FALSE(contains(run.output, "WARNING"));
        CHECK(contains(run.output, "urn:nclink:device:"));
    };
    for (const auto& c : cases())
        for (const auto profile : {OpcUaProfile::basic, OpcUaProfile::cnc}) {
            INFO(c.name << " " << to_string(profile));
            auto doc = map_to_opcua(*c.model, fixed_options(profile));
            REQUIRE(doc.ok());
            const std::string file = write_scratch(file_name(c.name, std::string(to_string(profile)) + ".load.NodeSet2"), doc->xml);
            if (profile == OpcUaProfile::basic) load("", file);
            else  // the appendix-B models with node-opcua-nodesets' own CNC copy
                load(c.name.rfind("appendix-b", 0) == 0 ? cnc_only : chain, file);
        }
}
