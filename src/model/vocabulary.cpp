// The vocabularies of GB/T 41970-2022 chapter 7, transcribed from the tables.
// One table serves the validator (is_*, suggest_*) and the reference
// docs/vocabulary.md (vocabulary_markdown(), vocabulary_doc.cpp).
#include "model/vocabulary.hpp"

#include "core/nearest.hpp"

#include <nclink/vocabulary.hpp>

#include <algorithm>
#include <cctype>
#include <iterator>

namespace nclink {

const std::vector<VocabularyTerm>& vocabulary_device_types() {
    // Table 7. (Appendix A spells AGV as "AVG"; the table is authoritative.)
    static const std::vector<VocabularyTerm> table{
        {"AGV", "table 7", "automated guided vehicle", "", "", ""},
        {"CLEAN", "table 7", "cleaning equipment", "", "", ""},
        {"MACHINE", "table 7", "machine tool", "", "", ""},
        {"MEASURE", "table 7", "measuring equipment", "", "", ""},
        {"PRODUCTLINE", "table 7", "automated production line", "", "", ""},
        {"WAREHOUSE", "table 7", "automated store", "", "", ""},
    };
    return table;
}

const std::vector<VocabularyTerm>& vocabulary_component_types() {
    // Table 8; AXIS numbers from table 9 (nclink models a spindle as AXIS "S",
    // docs/model.md).
    static const std::vector<VocabularyTerm> table{
        {"AUXILIARY", "table 8", "auxiliary system", "", "", ""},
        {"AXIS", "table 8", "axis; `number` per table 9: X Y Z, X1..Xn, A B C, U V W, J1..Jn (spindles: S)", "", "", ""},
        {"COMPONENT", "table 8", "other general part", "", "", ""},
        {"CONTROLLER", "table 8", "controller (CNC)", "", "", ""},
        {"FIXTURE", "table 8", "fixture", "", "", ""},
        {"MOTOR", "table 8", "motor", "", "", ""},
        {"SCREW", "table 8", "lead screw", "", "", ""},
        {"SENSOR", "table 8", "sensor", "", "", ""},
        {"SERVO_DRIVER", "table 8", "servo drive", "", "", ""},
        {"TOOL_MAGAZINE", "table 8", "tool magazine", "", "", ""},
    };
    return table;
}

const std::vector<VocabularyTerm>& vocabulary_data_types() {
    static const std::vector<VocabularyTerm> table{
        // table 10: physical quantities
        {"ACCELERATION", "table 10", "acceleration", "number", "mm/s²", ""},
        {"ANGLE", "table 10", "angular position", "number", "rad", ""},
        {"ANGULAR_ACCELERATION", "table 10", "angular acceleration", "number", "rad/s²", ""},
        {"ANGULAR_VELOCITY", "table 10", "angular velocity", "number", "rad/s", ""},
        {"CONCENTRATION", "table 10", "concentration", "number", "m/m", ""},
        {"CONDUCTIVITY", "table 10", "conductivity", "number", "S/m", ""},
        {"CURRENT", "table 10", "electric current", "number", "A", ""},
        {"DISPLACEMENT", "table 10", "displacement", "number", "mm", ""},
        {"ENERGY", "table 10", "energy consumed", "number", "kW·h", ""},
        {"FLOW", "table 10", "instantaneous flow", "number", "L/s", ""},
        {"FREQUENCY", "table 10", "frequency", "number", "Hz", ""},
        {"LENGTH", "table 10", "length", "number", "mm", ""},
        {"MASS", "table 10", "mass", "number", "kg", ""},
        {"PERIOD", "tables 10, 13", "period", "number", "s", ""},
        {"POSITION", "table 10", "position", "number", "mm", ""},
        {"POWER", "table 10", "power", "number", "W", ""},
        {"POWER_FACTOR", "table 10", "power factor", "number", "", ""},
        {"PRESSURE", "table 10", "pressure", "number", "Pa", ""},
        {"RESISTANCE", "table 10", "resistance", "number", "Ω", ""},
        {"ROTATION_SPEED", "table 10", "rotation speed", "number", "r/min", ""},
        {"SPEED", "table 10", "speed", "number", "mm/min", ""},
        {"TEMPERATURE", "table 10", "temperature", "number", "°C", ""},
        {"TORQUE", "table 10", "torque", "number", "N·m", ""},
        {"VISCOSITY", "table 10", "viscosity", "number", "Pa·s", ""},
        {"VOLT_AMPERE", "table 10", "apparent power", "number", "VA", ""},
        // table 12: general items
        {"CATAGORY", "table 12", "category (spelt so by the standard)", "string", "",
         "under AXIS: rotary, linear; under MACHINE: lathe, milling, grinder, planer, other (table 16)"},
        {"CREATE_TIME", "table 12", "creation time", "string", "", ""},
        {"CREATOR", "table 12", "creator", "string", "", ""},
        {"IP", "table 12", "network IP address", "string", "", ""},
        {"MANUFACTURER", "table 12", "manufacturer", "string", "", ""},
        {"MODEL", "table 12", "model", "string", "", ""},
        {"NAME", "table 12", "name", "string", "", ""},
        {"PARAMETER", "table 12", "parameters", "dict", "", ""},
        {"SERIAL_NUMBER", "table 12", "serial number", "number", "", ""},
        {"STATUS", "table 12", "running state of a device or component", "string", "", "running, free, holding (table 15)"},
        {"UPPER_LIMIT", "table 12", "upper limit of a quantity", "number", "", ""},
        {"USER_ROLE", "table 12", "user role", "string", "",
         "operator, manager, machine_manufacturer, cnc_manufacturer, system_manager (table 15)"},
        {"VARIABLE", "table 12", "run-time variables", "list", "", ""},
        {"VERSION", "table 12", "version", "string", "", ""},
        {"WARNING", "tables 12, 13", "alarm", "object: number, text, emerge_time, key_value (table 14)", "", ""},
        {"WORK_MODE", "table 12", "work mode", "string", "", "manual, auto (table 15)"},
        // table 13: special items
        {"AUTO_MODE", "table 13", "automatic mode", "Boolean", "", ""},
        {"AXIS_BACKLASH", "table 13", "axis backlash", "number", "mm", ""},
        {"AXIS_LOAD", "table 13", "axis load", "number", "kg", ""},
        {"AXIS_TOREFPOINT", "table 13", "axis at its reference point", "Boolean", "", ""},
        {"BLOCK_SKIP_MODE", "table 13", "block skip mode", "Boolean", "", ""},
        {"CHIP_REMOVAL", "table 13", "chip conveyor mode", "string", "", "forward, stop, reverse (table 15)"},
        {"COMPACITY", "table 13", "tool magazine capacity", "number", "", ""},
        {"CONSOLE", "table 13", "console", "string", "", ""},
        {"COOLANT_ON", "table 13", "coolant on", "Boolean", "", ""},
        {"COORDINATE", "table 13", "coordinate system", "object: name, x y z a b c u v w (x1..xn) (table 14)", "", ""},
        {"CYCLE_START", "table 13", "cycle start", "Boolean", "", ""},
        {"DOOR_CLOSED", "table 13", "door closed", "Boolean", "", ""},
        {"EDIT_MODE", "table 13", "edit mode", "Boolean", "", ""},
        {"EMG", "table 13", "emergency stop", "Boolean", "", ""},
        {"FEED_HOLD", "table 13", "feed hold", "Boolean", "", ""},
        {"FEED_OVERRIDE", "table 13", "feed override", "number", "", ""},
        {"FEED_SPEED", "table 13", "feed speed", "number", "mm/s", ""},
        {"FILE", "table 13", "file", "file", "", ""},
        {"FIXTURE_MODE", "table 13", "fixture state", "string", "", "loose, tight (table 15)"},
        {"HANDLE_MODE", "table 13", "handwheel mode", "Boolean", "", ""},
        {"INCREMENTAL_MODE", "table 13", "incremental mode", "Boolean", "", ""},
        {"JOG_MODE", "table 13", "jog mode", "Boolean", "", ""},
        {"LIGHTING_ON", "table 13", "work light on", "Boolean", "", ""},
        {"LINE_NUMBER", "table 13", "program line number", "string", "", ""},
        {"LUBRICANT_ON", "table 13", "lubrication on", "Boolean", "", ""},
        {"MACHINE_LOCKED", "table 13", "machine lock", "Boolean", "", ""},
        {"MDI_MODE", "table 13", "MDI mode", "Boolean", "", ""},
        {"MST_LOCKED", "table 13", "MST lock", "Boolean", "", ""},
        {"OPT_STOP_MODE", "table 13", "optional stop mode", "Boolean", "", ""},
        {"PATH_LEFT_LENGTH", "table 13", "remaining feed distance", "number", "mm", ""},
        {"PART", "table 13", "workpiece",
         "object: id, name, material, length, width, height, snap_shot, geometry_file, key_value (table 14)", "", ""},
        {"PART_COUNT", "table 13", "parts machined", "string", "", ""},
        {"PROGRAM", "table 13", "main program name", "string", "", ""},
        {"PROGRAM_MODE", "table 13", "program mode", "string", "", ""},
        {"PROGRAM_NUMBER", "table 13", "current program number", "number", "", ""},
        {"RAPID_OVERRIDE", "table 13", "rapid override", "number", "", ""},
        {"REF_MODE", "table 13", "reference return mode", "Boolean", "", ""},
        {"RESET_MODE", "table 13", "reset", "Boolean", "", ""},
        {"RESIDUAL", "table 13", "remaining quantity", "number", "", ""},
        {"SHELF_UNIT", "table 13", "storage places", "list", "", ""},
        {"SINGLE_BLOCK_MODE", "table 13", "single block mode", "Boolean", "", ""},
        {"SITE", "table 13", "AGV station", "string", "", ""},
        {"SPINDLE_MODE", "table 13", "spindle mode", "string", "", "forward, stop, reverse (table 15)"},
        {"SPINDLE_OVERRIDE", "table 13", "spindle override", "number", "", ""},
        {"SPINDLE_SPEED", "table 13", "spindle speed", "number", "r/min", ""},
        {"SUBPROGRAM", "table 13", "subprogram name", "string", "", ""},
        {"TOOL", "table 13", "tools", "list", "", ""},
        {"TOOL_CHANGE", "table 13", "tool change mode", "string", "", "auto, manual (table 15)"},
        {"TOOL_CHANGING", "table 13", "tool change in progress", "Boolean", "", ""},
        {"TOOL_PARAM", "table 13", "tool parameters", "object: type, id, name, kind, radius, length, ... (table 14)", "", ""},
        {"TOOL_NUMBER", "table 13", "current tool number", "number", "", ""},
        {"TOOL_POSITION", "table 13", "current tool pocket", "number", "", ""},
        // appendix A only: the `ValueTypeNames` enumeration lists it without a table row.
        {"RATE", "appendix A", "rate", "number", "", ""},
    };
    return table;
}

const std::vector<VocabularyUnits>& vocabulary_units() {
    // Default units of tables 10 and 13, non-default units of table 11 (both
    // the micro sign U+00B5 and the Greek mu U+03BC, since editors produce
    // either), and the appendix A `unitType` names.
    static const std::vector<VocabularyUnits> table{
        {"tables 10, 13 (default units)",
         {"mm/s²", "rad", "rad/s²", "rad/s", "m/m",   "S/m",    "A",  "mm",  "kW·h", "L/s", "Hz",  "kg",
          "s",     "W",   "Pa",     "Ω",     "r/min", "mm/min", "°C", "N·m", "Pa·s", "VA",  "mm/s"}},
        {"table 11 (other common units)", {"mA",  "μA", "µA", "m",  "μm", "µm", "W·h", "W·s",   "mL/s", "kHz", "MHz",
                                           "GHz", "g",  "mg", "kW", "mW", "kΩ", "MΩ",  "m/min", "°F",   "kVA"}},
        {"appendix A (unitType)",
         {"AMPERE",
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
          "MILLIMETER_3D",
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
          "OTHER"}},
        {"ASCII spellings (hand-written files)",
         {"mm/s^2", "rad/s^2", "kW.h", "N.m", "Pa.s", "W.h", "W.s", "um", "uA", "ohm", "kohm", "Mohm"}},
    };
    return table;
}

const std::vector<VocabularyAlias>& vocabulary_type_aliases() {
    // Abbreviations seen in deployed files (and appendix B) for table entries.
    static const std::vector<VocabularyAlias> table{
        {"SPDL_OVERRIDE", "SPINDLE_OVERRIDE", "abbreviation in deployed files"},
        {"SPDL_SPEED", "SPINDLE_SPEED", "abbreviation in deployed files"},
        {"CATEGORY", "CATAGORY", "table 12 spells it CATAGORY"},
        {"AVG", "AGV", "appendix A misspelling of table 7"},
        // Appendix A/B name these two data types differently from table 12:
        // TYPE holds an axis' linear/rotary (table 16 CATAGORY), NUMBER a number.
        {"TYPE", "CATAGORY", "appendix A/B name for table 12's CATAGORY"},
        {"NUMBER", "SERIAL_NUMBER", "appendix A/B name for table 12's SERIAL_NUMBER"},
    };
    return table;
}

const std::vector<VocabularyAlias>& vocabulary_hints() {
    static const std::vector<VocabularyAlias> table{
        {"SPINDLE", "AXIS with number \"S\"", "table 8 has no spindle component: a spindle is an axis"},
        {"CNC", "CONTROLLER", "table 8"},
        {"NC", "CONTROLLER", "table 8"},
        {"MAGAZINE", "TOOL_MAGAZINE", "table 8"},
        {"SERVO", "SERVO_DRIVER", "table 8"},
        {"rpm", "r/min", "table 10 (ROTATION_SPEED, SPINDLE_SPEED)"},
        {"RPM", "r/min", "table 10 (ROTATION_SPEED, SPINDLE_SPEED)"},
        {"deg", "DEGREE", "appendix A"},
        {"degC", "°C", "table 10"},
        {"C", "°C", "table 10"},
        {"%", "PERCENT", "appendix A"},
        {"sec", "s", "table 10"},
        {"V", "VOLT", "appendix A"},
        {"Nm", "N·m", "table 10"},
        {"kWh", "kW·h", "table 10"},
        {"mm/s2", "mm/s²", "table 10"},
    };
    return table;
}

namespace model_detail {
namespace {

bool in(const std::vector<VocabularyTerm>& table, std::string_view value) {
    return std::any_of(table.begin(), table.end(), [&](const VocabularyTerm& t) { return t.name == value; });
}

std::string upper(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

std::optional<std::string> suggest(const std::vector<VocabularyTerm>& table, std::string_view type) {
    const std::string up = upper(type);
    if (up != type && in(table, up)) return up;
    for (const auto& a : vocabulary_type_aliases())
        if (a.used == up && in(table, a.meant)) return std::string(a.meant);
    return std::nullopt;
}

std::optional<std::string> hint_or_nearest(const std::vector<std::string_view>& names, std::string_view text,
                                           bool components = false) {
    for (const auto& h : vocabulary_hints()) {
        if (h.used != text) continue;
        const bool axis = std::string_view(h.meant).rfind("AXIS ", 0) == 0;  // "AXIS with number ..."
        if ((axis && components) || std::find(names.begin(), names.end(), h.meant) != names.end()) return std::string(h.meant);
    }
    return core_detail::nearest_name(text, names);
}

std::vector<std::string_view> names(const std::vector<VocabularyTerm>& table) {
    std::vector<std::string_view> out;
    for (const auto& t : table) out.push_back(t.name);
    return out;
}

}  // namespace

bool is_device_type(std::string_view type) noexcept { return in(vocabulary_device_types(), type); }
bool is_component_type(std::string_view type) noexcept { return in(vocabulary_component_types(), type); }
bool is_data_type(std::string_view type) noexcept { return in(vocabulary_data_types(), type); }
bool is_known_unit(std::string_view units) noexcept {
    for (const auto& group : vocabulary_units())
        if (std::find(group.units.begin(), group.units.end(), units) != group.units.end()) return true;
    return false;
}

std::optional<std::string> suggest_data_type(std::string_view type) { return suggest(vocabulary_data_types(), type); }
std::optional<std::string> suggest_device_type(std::string_view type) { return suggest(vocabulary_device_types(), type); }
std::optional<std::string> suggest_component_type(std::string_view type) { return suggest(vocabulary_component_types(), type); }

std::optional<std::string> nearest_data_type(std::string_view type) {
    return hint_or_nearest(names(vocabulary_data_types()), type);
}
std::optional<std::string> nearest_device_type(std::string_view type) {
    return hint_or_nearest(names(vocabulary_device_types()), type);
}
std::optional<std::string> nearest_component_type(std::string_view type) {
    return hint_or_nearest(names(vocabulary_component_types()), type, true);
}
std::optional<std::string> nearest_unit(std::string_view units) {
    std::vector<std::string_view> all;
    for (const auto& group : vocabulary_units()) all.insert(all.end(), group.units.begin(), group.units.end());
    for (const auto& h : vocabulary_hints())
        if (h.used == units && std::find(all.begin(), all.end(), h.meant) != all.end()) return std::string(h.meant);
    return core_detail::nearest_name(units, all);
}

}  // namespace model_detail
}  // namespace nclink
