// The mapping tables: complete over chapter 7, consistent with themselves and
// with the MTConnect 1.4 schemas they claim to follow.
#include "mapping_test_util.hpp"

#include "mapping/mapping_table.hpp"
#include "model/vocabulary.hpp"

#include <catch2/catch.hpp>

#include <map>

#include <regex>

using namespace nclink;
using namespace nclink::mapping_detail;

namespace {

// GB/T 41970-2022 tables 10, 12 and 13, transcribed here independently of
// src/model/vocabulary.cpp and src/mapping/mapping_table.cpp.
const char* const kChapter7DataTypes[] = {"ACCELERATION",
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
                                          "TOOL_POSITION"};

const char* const kTable8[] = {"AUXILIARY", "AXIS",  "COMPONENT", "CONTROLLER",   "FIXTURE",
                               "MOTOR",     "SCREW", "SENSOR",    "SERVO_DRIVER", "TOOL_MAGAZINE"};

Placement on_device() {
    Placement p;
    p.on_device = true;
    return p;
}
Placement on_controller() {
    Placement p;
    p.on_controller = true;
    return p;
}
Placement on_axis() {
    Placement p;
    p.on_axis = true;
    return p;
}
Placement in_axis() {
    Placement p;
    p.in_axis = true;
    return p;
}

/// Every value="..." of an xs:simpleType in a schema file.
std::vector<std::string> enumeration(const std::string& xsd, const std::string& type) {
    const auto start = xsd.find("<xs:simpleType name=\"" + type + "\"");
    REQUIRE(start != std::string::npos);
    const auto end = xsd.find("</xs:simpleType>", start);
    std::vector<std::string> values;
    const std::regex value("value=\"([^\"]+)\"");
    const std::string body = xsd.substr(start, end - start);
    for (std::sregex_iterator it(body.begin(), body.end(), value), last; it != last; ++it) values.push_back((*it)[1]);
    return values;
}

bool in(const std::vector<std::string>& list, std::string_view word) {
    return std::find(list.begin(), list.end(), word) != list.end();
}

}  // namespace

TEST_CASE("every chapter-7 data type has a mapping row wherever it sits") {
    for (const char* type : kChapter7DataTypes) {
        INFO(type);
        CHECK(model_detail::is_data_type(type));
        for (const Placement& p : {Placement{}, on_device(), on_controller(), on_axis(), in_axis()})
            CHECK(find_data_row(type, p) != nullptr);
    }
    CHECK(find_data_row("NO_SUCH_TYPE", {}) == nullptr);
    CHECK(unknown_type_row().mt_fallback);
}

TEST_CASE("every table-8 component type has a row and other types fall back to System") {
    for (const char* type : kTable8) {
        INFO(type);
        REQUIRE(find_component_row(type) != nullptr);
    }
    CHECK(find_component_row("TURRET") == nullptr);
    CHECK(unknown_component_row().element == "System");
    CHECK(find_component_row("CONTROLLER")->element == "Controller");
    CHECK(find_component_row("AXIS")->in_axes);
    CHECK(find_component_row("SENSOR")->element == "Sensor");
    CHECK(find_component_row("TOOL_MAGAZINE")->element == "ToolingDelivery");
    CHECK(find_component_row("SERVO_DRIVER")->ua_kind == UaObjectKind::actuator);
    CHECK(find_component_row("AXIS")->ua_kind == UaObjectKind::axes);
    CHECK(find_component_row("CONTROLLER")->ua_kind == UaObjectKind::controller);
}

TEST_CASE("data rows follow appendix A where it gives a row") {
    struct Expect {
        const char* type;
        Placement placement;
        MtCategory category;
        const char* mt_type;
        const char* sub_type;
        const char* element;
    };
    const Expect expected[] = {
        {"POSITION", {}, MtCategory::sample, "POSITION", "ACTUAL", "Position"},                    // A.5 0x2106
        {"SPINDLE_SPEED", {}, MtCategory::sample, "ROTARY_VELOCITY", "ACTUAL", "RotaryVelocity"},  // 0x2008
        {"FEED_SPEED", {}, MtCategory::sample, "PATH_FEEDRATE", "ACTUAL", "PathFeedrate"},         // 0x212D
        {"FEED_OVERRIDE", {}, MtCategory::event, "PATH_FEEDRATE_OVERRIDE", "PROGRAMMED", "PathFeedrateOverride"},
        {"AXIS_LOAD", {}, MtCategory::sample, "LOAD", "", "Load"},                      // 0x2124
        {"AXIS_BACKLASH", {}, MtCategory::sample, "DISPLACEMENT", "", "Displacement"},  // 0x211E
        {"PATH_LEFT_LENGTH", {}, MtCategory::sample, "LENGTH", "REMAINING", "Length"},  // 0x2118
        {"PART_COUNT", {}, MtCategory::event, "PART_COUNT", "ALL", "PartCount"},        // 0x1007
        {"PROGRAM", {}, MtCategory::event, "PROGRAM", "", "Program"},                   // 0x1000
        {"SUBPROGRAM", {}, MtCategory::event, "PROGRAM", "", "Program"},                // 0x1001
        {"EMG", {}, MtCategory::event, "EMERGENCY_STOP", "", "EmergencyStop"},          // 0x4002
        {"WARNING", {}, MtCategory::condition, "SYSTEM", "", ""},                       // 0x0108
        {"WORK_MODE", {}, MtCategory::event, "CONTROLLER_MODE", "", "ControllerMode"},  // 0x0101
        {"SPINDLE_MODE", {}, MtCategory::event, "DIRECTION", "ROTARY", "Direction"},    // 0x200B
        {"TEMPERATURE", {}, MtCategory::sample, "TEMPERATURE", "", "Temperature"},      // 0x5000
        {"PERIOD", {}, MtCategory::sample, "ACCUMULATED_TIME", "", "AccumulatedTime"},  // 0x5018
        {"CURRENT", {}, MtCategory::sample, "AMPERAGE", "ACTUAL", "Amperage"},          // A.6 0x100A
        {"STATUS", on_controller(), MtCategory::event, "EXECUTION", "", "Execution"},
        {"STATUS", on_device(), MtCategory::event, "EXECUTION", "", "Execution"},
        {"STATUS", in_axis(), MtCategory::event, "ACTUATOR_STATE", "", "ActuatorState"},
        {"SPEED", on_axis(), MtCategory::sample, "AXIS_FEEDRATE", "ACTUAL", "AxisFeedrate"},
        {"SPEED", in_axis(), MtCategory::sample, "AXIS_FEEDRATE", "ACTUAL", "AxisFeedrate"},
        {"SPEED", on_device(), MtCategory::sample, "VELOCITY", "", "Velocity"},
        {"SINGLE_BLOCK_MODE", {}, MtCategory::event, "CONTROLLER_MODE_OVERRIDE", "SINGLE_BLOCK", "ControllerModeOverride"},
        {"MACHINE_LOCKED", {}, MtCategory::event, "CONTROLLER_MODE_OVERRIDE", "MACHINE_AXIS_LOCK", "ControllerModeOverride"},
        {"TOOL_NUMBER", {}, MtCategory::event, "TOOL_NUMBER", "", "ToolNumber"},
    };
    for (const auto& e : expected) {
        INFO(e.type);
        const DataTypeRow* row = find_data_row(e.type, e.placement);
        REQUIRE(row != nullptr);
        CHECK_FALSE(row->mt_fallback);
        CHECK(row->category == e.category);
        CHECK(row->mt_type == e.mt_type);
        CHECK(row->mt_sub_type == e.sub_type);
        CHECK(row->element == e.element);
    }
}

TEST_CASE("types without an MTConnect 1.4 DataItem type are fallback rows with a reason") {
    for (const char* type :
         {"TOOL", "TOOL_PARAM", "PARAMETER", "VERSION", "AUTO_MODE", "MST_LOCKED", "BLOCK_SKIP_MODE", "CHIP_REMOVAL", "RATE"}) {
        INFO(type);
        const DataTypeRow* row = find_data_row(type, {});
        REQUIRE(row != nullptr);
        CHECK(row->mt_fallback);
        CHECK(row->mt_type == "MESSAGE");
        CHECK(row->element == "Message");
        CHECK_FALSE(row->clause.empty());
    }
}

TEST_CASE("enumerated rows translate every word of tables 15 and 16") {
    const auto values = [](const char* type, Placement p) {
        const DataTypeRow* row = find_data_row(type, p);
        REQUIRE(row != nullptr);
        REQUIRE(row->value_form == MtValueForm::enumerated);
        std::map<std::string, std::string> out;
        for (std::size_t i = 0; i < row->value_count; ++i)
            out[std::string(row->values[i].nclink)] = std::string(row->values[i].mtconnect);
        return out;
    };
    const auto execution = values("STATUS", on_controller());
    CHECK(execution.at("running") == "ACTIVE");
    CHECK(execution.at("free") == "READY");
    CHECK(execution.at("holding") == "FEED_HOLD");
    const auto actuator = values("STATUS", in_axis());
    CHECK(actuator.at("running") == "ACTIVE");
    CHECK(actuator.at("free") == "INACTIVE");
    const auto mode = values("WORK_MODE", {});
    CHECK(mode.at("manual") == "MANUAL");
    CHECK(mode.at("auto") == "AUTOMATIC");
    CHECK(values("EMG", {}).at("true") == "TRIGGERED");
    CHECK(values("EMG", {}).at("false") == "ARMED");
    CHECK(values("DOOR_CLOSED", {}).at("true") == "CLOSED");
    CHECK(values("SPINDLE_MODE", {}).at("reverse") == "COUNTER_CLOCKWISE");
    CHECK(values("FIXTURE_MODE", {}).at("tight") == "ACTIVE");
}

TEST_CASE("OPC UA kinds follow tables B.8 B.10 and B.11") {
    CHECK(find_data_row("POSITION", {})->ua_kind == UaKind::analog);
    CHECK(find_data_row("POSITION", {})->ua_data_type == "Double");
    CHECK(find_data_row("EMG", {})->ua_kind == UaKind::two_state);
    CHECK(find_data_row("EMG", {})->ua_data_type == "Boolean");
    const DataTypeRow* status = find_data_row("STATUS", {});
    CHECK(status->ua_kind == UaKind::multi_state);
    CHECK(status->ua_data_type == "UInt32");
    REQUIRE(status->enum_count == 3);
    CHECK(status->enum_strings[0] == "running");
    // Two words (B.10): TwoStateDiscreteType, first word true.
    const DataTypeRow* work_mode = find_data_row("WORK_MODE", {});
    CHECK(work_mode->ua_kind == UaKind::two_state);
    CHECK(work_mode->true_state == "auto");
    CHECK(work_mode->false_state == "manual");
    CHECK(find_data_row("CATAGORY", on_axis())->ua_kind == UaKind::two_state);
    CHECK(find_data_row("CATAGORY", on_device())->ua_kind == UaKind::multi_state);
    CHECK(find_data_row("CATAGORY", in_axis())->ua_kind == UaKind::data_item);
    CHECK(find_data_row("PROGRAM", {})->ua_kind == UaKind::data_item);
    CHECK(find_data_row("TOOL_NUMBER", {})->ua_data_type == "Int32");
    // MASS falls back in MTConnect (no Streams element) but stays analog in OPC UA.
    CHECK(find_data_row("MASS", {})->mt_fallback);
    CHECK(find_data_row("MASS", {})->ua_kind == UaKind::analog);
    CHECK(find_data_row("MASS", {})->default_units == "kg");
}

TEST_CASE("units convert to MTConnect's units and carry UNECE codes") {
    const UnitRow* mm_min = find_unit("mm/min");
    REQUIRE(mm_min != nullptr);
    CHECK(mm_min->dimension == Dimension::velocity);
    CHECK(mm_min->scale == Approx(1.0 / 60));
    CHECK(mm_min->native_units == "MILLIMETER/MINUTE");
    CHECK(mm_min->unece == "H81");
    CHECK(mm_min->unit_id == 4732977);
    CHECK(mtconnect_units(Dimension::velocity) == "MILLIMETER/SECOND");

    const UnitRow* rad = find_unit("rad");
    REQUIRE(rad != nullptr);
    CHECK(rad->scale * 3.141592653589793 == Approx(180));
    const UnitRow* fahrenheit = find_unit("°F");
    REQUIRE(fahrenheit != nullptr);
    CHECK(212 * fahrenheit->scale + fahrenheit->offset == Approx(100));
    CHECK(32 * fahrenheit->scale + fahrenheit->offset == Approx(0).margin(1e-12));
    CHECK(find_unit("kW·h")->scale == Approx(3.6e6));
    CHECK(find_unit("PERCENT")->unece == "P1");
    CHECK(find_unit("PERCENT")->unit_id == 20529);
    CHECK(find_unit("mm")->unit_id == 5066068);
    CHECK(find_unit("r/min")->unece == "RPM");
    CHECK(find_unit("furlong") == nullptr);

    // UnitId is the UNECE code's characters packed into an Int32 (OPC 10000-8 5.6.3).
    for (const char* spelling : {"mm", "A", "°C", "N·m", "PERCENT", "rad/s", "kHz", "mL/s"}) {
        const UnitRow* u = find_unit(spelling);
        REQUIRE(u != nullptr);
        std::int32_t id = 0;
        for (const char c : u->unece) id = (id << 8) | static_cast<unsigned char>(c);
        CHECK(id == u->unit_id);
    }
}

TEST_CASE("every table-10/11 and appendix-A unit the model accepts is in the unit table") {
    for (const char* unit : {"mm/s²",
                             "rad",
                             "rad/s²",
                             "rad/s",
                             "m/m",
                             "S/m",
                             "A",
                             "mm",
                             "kW·h",
                             "L/s",
                             "Hz",
                             "kg",
                             "s",
                             "W",
                             "Pa",
                             "Ω",
                             "r/min",
                             "mm/min",
                             "°C",
                             "N·m",
                             "Pa·s",
                             "VA",
                             "mm/s",
                             "mA",
                             "μA",
                             "µA",
                             "m",
                             "μm",
                             "µm",
                             "W·h",
                             "W·s",
                             "mL/s",
                             "kHz",
                             "MHz",
                             "GHz",
                             "g",
                             "mg",
                             "kW",
                             "mW",
                             "kΩ",
                             "MΩ",
                             "m/min",
                             "°F",
                             "kVA",
                             "AMPERE",
                             "CELSIUS",
                             "COUNT",
                             "DEGREE",
                             "DEGREE/SECOND",
                             "DEGREE/SECOND^2",
                             "HERTZ",
                             "JOULE",
                             "KILOGRAM",
                             "LITER",
                             "LITER/SECOND",
                             "MILLIMETER",
                             "MILLIMETER/SECOND",
                             "MILLIMETER/SECOND^2",
                             "NEWTON",
                             "NEWTON_METER",
                             "PASCAL",
                             "PERCENT",
                             "PH",
                             "REVOLUTION/MINUTE",
                             "SECOND",
                             "VOLT",
                             "WATT",
                             "OHM",
                             "SOUND_LEVEL",
                             "SIEMENS/METER",
                             "MICRO_RADIAN",
                             "PASCAL_SECOND",
                             "VOLT_AMPERE",
                             "VOLT_AMPERE_REACTIVE",
                             "WATT_SECOND",
                             "DECIBEL",
                             "CENTIPOISE",
                             "DEGREE/MINUTE",
                             "FAHRENHEIT",
                             "KILOWATT",
                             "KILOWATT_HOUR",
                             "MILLIMETER/MINUTE",
                             "RADIAN",
                             "RADIAN/MINUTE",
                             "RADIAN/SECOND",
                             "RADIAN/SECOND^2",
                             "REVOLUTION/SECOND",
                             "mm/s^2",
                             "rad/s^2",
                             "kW.h",
                             "N.m",
                             "Pa.s",
                             "W.h",
                             "W.s",
                             "um",
                             "uA",
                             "ohm",
                             "kohm",
                             "Mohm"}) {
        INFO(unit);
        CHECK(model_detail::is_known_unit(unit));
        CHECK(find_unit(unit) != nullptr);
    }
}

TEST_CASE("every MTConnect name in the tables is defined by the 1.4 schemas") {
    const std::string dir = test::interop_dir();
    if (dir.empty()) {
        WARN("SKIPPED: shared interop fixtures not found (set NCLINK_INTEROP_DIR)");
        return;
    }
    const std::string devices = test::read_text(dir + "/mtconnect-schema/MTConnectDevices_1.4_1.0.xsd");
    const std::string streams = test::read_text(dir + "/mtconnect-schema/MTConnectStreams_1.4_1.0.xsd");
    const auto types = enumeration(devices, "DataItemEnumTypeEnum");
    const auto sub_types = enumeration(devices, "DataItemSubEnumTypeEnum");
    const auto units = enumeration(devices, "UnitsTypeEnum");
    const auto native = enumeration(devices, "NativeUnitsTypeEnum");
    const std::regex extension("x:[A-Z_0-9]+");
    for (std::size_t i = 0; i < data_row_count(); ++i) {
        const DataTypeRow& row = data_row(i);
        INFO(row.type);
        CHECK(in(types, row.mt_type));
        if (!row.mt_sub_type.empty()) CHECK(in(sub_types, row.mt_sub_type));
        if (!row.element.empty()) CHECK(test::contains(streams, "<xs:element name=\"" + std::string(row.element) + "\""));
        if (row.dimension != Dimension::none) CHECK(in(units, mtconnect_units(row.dimension)));
    }
    for (const char* spelling : {"mm", "m", "mm/min", "m/min", "rad", "rad/s", "mA", "kW·h", "W·h", "kW", "kΩ", "°F", "m/m",
                                 "CENTIPOISE", "kVA", "g", "kHz"}) {
        const UnitRow* u = find_unit(spelling);
        REQUIRE(u != nullptr);
        INFO(spelling);
        CHECK(in(units, mtconnect_units(u->dimension)));
        if (!u->native_units.empty())
            CHECK((in(native, u->native_units) || std::regex_match(std::string(u->native_units), extension)));
    }
    for (std::size_t i = 0; i < component_row_count(); ++i)
        CHECK(test::contains(devices, "<xs:element name=\"" + std::string(component_row(i).element) + "\""));
}
