// The vocabularies of GB/T 41970-2022 chapter 7, transcribed from the tables.
#include "model/vocabulary.hpp"

#include <algorithm>
#include <iterator>
#include <cctype>

namespace nclink::model_detail {
namespace {

// Table 7. (Appendix A spells AGV as "AVG"; the table is authoritative.)
constexpr std::string_view kDeviceTypes[] = {
    "AGV", "CLEAN", "MACHINE", "MEASURE", "PRODUCTLINE", "WAREHOUSE"};

// Table 8.
constexpr std::string_view kComponentTypes[] = {
    "AUXILIARY", "AXIS",  "COMPONENT", "CONTROLLER",   "FIXTURE",
    "MOTOR",     "SCREW", "SENSOR",    "SERVO_DRIVER", "TOOL_MAGAZINE"};

// Tables 10 (physical), 12 (general) and 13 (special); RATE comes from the
// appendix A enumeration `ValueTypeNames`, which lists it without a table row.
constexpr std::string_view kDataTypes[] = {
    // table 10
    "ACCELERATION", "ANGLE", "ANGULAR_ACCELERATION", "ANGULAR_VELOCITY", "CONCENTRATION",
    "CONDUCTIVITY", "CURRENT", "DISPLACEMENT", "ENERGY", "FLOW", "FREQUENCY", "LENGTH", "MASS",
    "PERIOD", "POSITION", "POWER", "POWER_FACTOR", "PRESSURE", "RESISTANCE", "ROTATION_SPEED",
    "SPEED", "TEMPERATURE", "TORQUE", "VISCOSITY", "VOLT_AMPERE",
    // table 12
    "CATAGORY", "CREATE_TIME", "CREATOR", "IP", "MANUFACTURER", "MODEL", "NAME", "PARAMETER",
    "SERIAL_NUMBER", "STATUS", "UPPER_LIMIT", "USER_ROLE", "VARIABLE", "VERSION", "WARNING",
    "WORK_MODE",
    // table 13
    "AUTO_MODE", "AXIS_BACKLASH", "AXIS_LOAD", "AXIS_TOREFPOINT", "BLOCK_SKIP_MODE",
    "CHIP_REMOVAL", "COMPACITY", "CONSOLE", "COOLANT_ON", "COORDINATE", "CYCLE_START",
    "DOOR_CLOSED", "EDIT_MODE", "EMG", "FEED_HOLD", "FEED_OVERRIDE", "FEED_SPEED", "FILE",
    "FIXTURE_MODE", "HANDLE_MODE", "INCREMENTAL_MODE", "JOG_MODE", "LIGHTING_ON", "LINE_NUMBER",
    "LUBRICANT_ON", "MACHINE_LOCKED", "MDI_MODE", "MST_LOCKED", "OPT_STOP_MODE",
    "PATH_LEFT_LENGTH", "PART", "PART_COUNT", "PROGRAM", "PROGRAM_MODE", "PROGRAM_NUMBER",
    "RAPID_OVERRIDE", "REF_MODE", "RESET_MODE", "RESIDUAL", "SHELF_UNIT", "SINGLE_BLOCK_MODE",
    "SITE", "SPINDLE_MODE", "SPINDLE_OVERRIDE", "SPINDLE_SPEED", "SUBPROGRAM", "TOOL",
    "TOOL_CHANGE", "TOOL_CHANGING", "TOOL_PARAM", "TOOL_NUMBER", "TOOL_POSITION",
    // appendix A only
    "RATE"};  // table 13 repeats PERIOD and WARNING; listed once above

// Default units of tables 10 and 13, non-default units of table 11 (both the
// micro sign U+00B5 and the Greek mu U+03BC, since editors produce either),
// and the appendix A `unitType` names.
constexpr std::string_view kUnits[] = {
    // table 10 / 13 defaults
    "mm/s²", "rad", "rad/s²", "rad/s", "m/m", "S/m", "A", "mm", "kW·h", "L/s", "Hz", "kg", "s",
    "W", "Pa", "Ω", "r/min", "mm/min", "°C", "N·m", "Pa·s", "VA", "mm/s",
    // table 11
    "mA", "μA", "µA", "m", "μm", "µm", "W·h", "W·s", "mL/s", "kHz", "MHz", "GHz", "g", "mg",
    "kW", "mW", "kΩ", "MΩ", "m/min", "°F", "kVA",
    // appendix A unitType
    "AMPERE", "CELSIUS", "COUNT", "DEGREE", "DEGREE/SECOND", "DEGREE/SECOND^2", "HERTZ",
    "JOULE", "KILOGRAM", "LITER", "LITER/SECOND", "MILLIMETER", "MILLIMETER/SECOND",
    "MILLIMETER/SECOND^2", "MILLIMETER_3D", "NEWTON", "NEWTON_METER", "PASCAL", "PERCENT", "PH",
    "REVOLUTION/MINUTE", "SECOND", "VOLT", "WATT", "OHM", "SOUND_LEVEL", "SIEMENS/METER",
    "MICRO_RADIAN", "PASCAL_SECOND", "VOLT_AMPERE", "VOLT_AMPERE_REACTIVE", "WATT_SECOND",
    "DECIBEL", "CENTIPOISE", "DEGREE/MINUTE", "FAHRENHEIT", "KILOWATT", "KILOWATT_HOUR",
    "MILLIMETER/MINUTE", "RADIAN", "RADIAN/MINUTE", "RADIAN/SECOND", "RADIAN/SECOND^2",
    "REVOLUTION/SECOND", "OTHER",
    // ASCII spellings of the superscript-2 units, common in hand-written files
    "mm/s^2", "rad/s^2", "kW.h", "N.m", "Pa.s", "W.h", "W.s", "um", "uA", "ohm", "kohm",
    "Mohm"};

// Abbreviations seen in deployed files (and appendix B) for table entries.
struct Abbreviation {
    std::string_view used;
    std::string_view meant;
};
constexpr Abbreviation kAbbreviations[] = {
    {"SPDL_OVERRIDE", "SPINDLE_OVERRIDE"},
    {"SPDL_SPEED", "SPINDLE_SPEED"},
    {"CATEGORY", "CATAGORY"},
    {"AVG", "AGV"},
    // Appendix A/B name these two data types differently from table 12:
    // TYPE holds an axis' linear/rotary (table 16 CATAGORY), NUMBER a number.
    {"TYPE", "CATAGORY"},
    {"NUMBER", "SERIAL_NUMBER"},
};

template <std::size_t N>
bool contains(const std::string_view (&table)[N], std::string_view value) {
    return std::find(std::begin(table), std::end(table), value) != std::end(table);
}

std::string upper(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

template <std::size_t N>
std::optional<std::string> suggest(const std::string_view (&table)[N],
                                   std::string_view type) {
    const std::string up = upper(type);
    if (up != type && contains(table, up)) return up;
    for (const auto& a : kAbbreviations)
        if (a.used == up && contains(table, a.meant)) return std::string(a.meant);
    return std::nullopt;
}

}  // namespace

bool is_device_type(std::string_view type) noexcept { return contains(kDeviceTypes, type); }
bool is_component_type(std::string_view type) noexcept { return contains(kComponentTypes, type); }
bool is_data_type(std::string_view type) noexcept { return contains(kDataTypes, type); }
bool is_known_unit(std::string_view units) noexcept { return contains(kUnits, units); }

std::optional<std::string> suggest_data_type(std::string_view type) {
    return suggest(kDataTypes, type);
}
std::optional<std::string> suggest_device_type(std::string_view type) {
    return suggest(kDeviceTypes, type);
}
std::optional<std::string> suggest_component_type(std::string_view type) {
    return suggest(kComponentTypes, type);
}

}  // namespace nclink::model_detail
