// Chapter 7 of GB/T 41970-2022 as data: the value of each data object type.
// Where the tables and appendix A disagree both readings are accepted and
// docs/wire.md says so: STATUS also as the integers 0/1/2 (appendix A),
// PARAMETER also as an array (appendix A), TOOL_PARAM radius/length and
// their compensations also as strings (appendix A).
#include "model/value_tables.hpp"

#include <cctype>
#include <map>
#include <string>

namespace nclink::model_detail {
namespace {

using S = ValueShape;

// Table 14 (and appendix A) objects. Required keys are the ones that say
// what the object is: a coordinate system's name, a part's or tool's id, a
// warning's number and text.
const ObjectSpec kCoordinate{"COORDINATE", {{"name", S::string, true}}, true};
const ObjectSpec kPart{"PART",
                       {{"id", S::string, true},
                        {"name", S::string},
                        {"material", S::string},
                        {"length", S::number},
                        {"width", S::number},
                        {"height", S::number},
                        {"snap_shot", S::file},
                        {"geometry_file", S::file},
                        {"key_value", S::object}}};
const ObjectSpec kToolParam{"TOOL_PARAM",
                            {{"type", S::string},
                             {"id", S::string, true},
                             {"name", S::string},
                             {"kind", S::string},
                             {"radius", S::number_or_string},
                             {"length", S::number_or_string},
                             {"time_usage", S::number},
                             {"max_time_usage", S::number},
                             {"count_usage", S::number},
                             {"max_count_usage", S::number},
                             {"length_process", S::number},
                             {"max_length_process", S::number},
                             {"radius_abaration", S::number_or_string},
                             {"length_abaration", S::number_or_string},
                             {"key_value", S::object}}};
const ObjectSpec kWarning{
    "WARNING", {{"number", S::string, true}, {"text", S::string, true}, {"emerge_time", S::number}, {"key_value", S::object}}};
// FILE: 6.2.1 names "file" a data type without giving its form, appendix A
// makes it a DICT. nclink's file object (docs/values.md): the file's name
// (required), where it is, its size in bytes (8.2.24's example gives sizes
// as strings: both), its time, and optionally its content with the content's
// encoding.
const ObjectSpec kFile{"FILE",
                       {{"name", S::string, true},
                        {"path", S::string},
                        {"size", S::number_or_string},
                        {"time", S::number_or_string},
                        {"encoding", S::string},
                        {"content", S::string}}};

TypeSpec number(std::string_view where, bool non_negative = false) {
    TypeSpec t;
    t.shape = S::number;
    t.where = where;
    t.has_min = non_negative;
    return t;
}

TypeSpec shape(S s, std::string_view where) {
    TypeSpec t;
    t.shape = s;
    t.where = where;
    return t;
}

TypeSpec enumerated(std::vector<std::string_view> values) {
    TypeSpec t;
    t.shape = S::string;
    t.where = "table 15";
    t.enumeration = std::move(values);
    return t;
}

TypeSpec object(const ObjectSpec& spec) {
    TypeSpec t;
    t.shape = S::object;
    t.where = "table 14";
    t.object = &spec;
    return t;
}

const std::map<std::string_view, TypeSpec>& specs() {
    static const std::map<std::string_view, TypeSpec> table = [] {
        std::map<std::string_view, TypeSpec> m;
        // Table 10: physical quantities, numbers. Those that cannot be
        // negative keep their lower bound of 0.
        for (auto type : {"ACCELERATION", "ANGLE", "ANGULAR_ACCELERATION", "ANGULAR_VELOCITY", "CURRENT", "DISPLACEMENT", "FLOW",
                          "POSITION", "POWER", "PRESSURE", "ROTATION_SPEED", "SPEED", "TORQUE"})
            m[type] = number("table 10");
        for (auto type : {"CONCENTRATION", "CONDUCTIVITY", "ENERGY", "FREQUENCY", "LENGTH", "MASS", "PERIOD", "RESISTANCE",
                          "VISCOSITY", "VOLT_AMPERE"})
            m[type] = number("table 10", true);
        TypeSpec power_factor = number("table 10");
        power_factor.has_min = power_factor.has_max = true;
        power_factor.min = -1;
        power_factor.max = 1;
        m["POWER_FACTOR"] = power_factor;
        TypeSpec temperature = number("table 10");
        temperature.has_min = true;
        temperature.temperature = true;
        m["TEMPERATURE"] = temperature;

        // Table 12: general items.
        for (auto type : {"CREATE_TIME", "CREATOR", "IP", "MANUFACTURER", "MODEL", "NAME", "VERSION"})
            m[type] = shape(S::string, "table 12");
        TypeSpec catagory = shape(S::string, "table 16");  // values depend on the parent: compiled per item
        m["CATAGORY"] = catagory;
        m["PARAMETER"] = shape(S::dict, "table 12");
        m["SERIAL_NUMBER"] = number("table 12");
        m["UPPER_LIMIT"] = number("table 12", true);
        TypeSpec status = enumerated({"running", "free", "holding"});
        status.int_enumeration = {0, 1, 2};  // appendix A: running, free, holding
        m["STATUS"] = status;
        m["USER_ROLE"] = enumerated({"operator", "manager", "machine_manufacturer", "cnc_manufacturer", "system_manager"});
        m["VARIABLE"] = shape(S::array, "table 12");
        m["WARNING"] = object(kWarning);
        m["WORK_MODE"] = enumerated({"manual", "auto"});

        // Table 13: special items.
        for (auto type : {"AUTO_MODE",         "AXIS_TOREFPOINT", "BLOCK_SKIP_MODE",  "COOLANT_ON",
                          "CYCLE_START",       "DOOR_CLOSED",     "EDIT_MODE",        "EMG",
                          "FEED_HOLD",         "HANDLE_MODE",     "INCREMENTAL_MODE", "JOG_MODE",
                          "LIGHTING_ON",       "LUBRICANT_ON",    "MACHINE_LOCKED",   "MDI_MODE",
                          "MST_LOCKED",        "OPT_STOP_MODE",   "REF_MODE",         "RESET_MODE",
                          "SINGLE_BLOCK_MODE", "TOOL_CHANGING"})
            m[type] = shape(S::boolean, "table 13");
        for (auto type : {"CONSOLE", "LINE_NUMBER", "PART_COUNT", "PROGRAM", "PROGRAM_MODE", "SITE", "SUBPROGRAM"})
            m[type] = shape(S::string, "table 13");
        for (auto type : {"AXIS_LOAD", "FEED_SPEED", "SPINDLE_SPEED"}) m[type] = number("table 13");
        for (auto type : {"AXIS_BACKLASH", "COMPACITY", "FEED_OVERRIDE", "PATH_LEFT_LENGTH", "PROGRAM_NUMBER", "RAPID_OVERRIDE",
                          "RESIDUAL", "SPINDLE_OVERRIDE", "TOOL_NUMBER", "TOOL_POSITION"})
            m[type] = number("table 13", true);
        m["CHIP_REMOVAL"] = enumerated({"forward", "stop", "reverse"});
        m["FIXTURE_MODE"] = enumerated({"loose", "tight"});
        m["SPINDLE_MODE"] = enumerated({"forward", "stop", "reverse"});
        m["TOOL_CHANGE"] = enumerated({"auto", "manual"});
        m["COORDINATE"] = object(kCoordinate);
        m["PART"] = object(kPart);
        m["TOOL_PARAM"] = object(kToolParam);
        TypeSpec file = shape(S::file, "table 13");
        file.object = &kFile;
        m["FILE"] = file;
        for (auto type : {"SHELF_UNIT", "TOOL"}) m[type] = shape(S::array, "table 13");
        return m;
    }();
    return table;
}

}  // namespace

const TypeSpec* type_spec(std::string_view type) noexcept {
    const auto& m = specs();
    const auto it = m.find(type);
    return it == m.end() ? nullptr : &it->second;
}

const ObjectSpec& file_object() noexcept { return kFile; }

const std::vector<std::string_view>& catagory_values(std::string_view parent_type) noexcept {
    static const std::vector<std::string_view> axis = {"rotary", "linear"};
    static const std::vector<std::string_view> machine = {"lathe", "milling", "grinder", "planer", "other"};
    static const std::vector<std::string_view> none;
    if (parent_type == "AXIS") return axis;
    if (parent_type == "MACHINE") return machine;
    return none;
}

double absolute_zero(std::string_view units) noexcept {
    if (units == "°F" || units == "FAHRENHEIT") return -459.67;
    if (units == "K" || units == "KELVIN") return 0;
    return -273.15;  // table 10: °C (also CELSIUS, and any unit we do not know)
}

bool is_axis_key(std::string_view key) noexcept {
    if (key.empty()) return false;
    const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(key[0])));
    if (std::string_view("xyzabcuvw").find(c) == std::string_view::npos) return false;
    for (std::size_t i = 1; i < key.size(); ++i)
        if (!std::isdigit(static_cast<unsigned char>(key[i]))) return false;
    return true;
}

}  // namespace nclink::model_detail
