// The mapping tables (see mapping_table.hpp). Every row names the clause it
// follows: "A.5 0x2106" is a row of GB/T 39561.3 table A.5 (its source-model
// index), "A.2 row 3" a row of table A.2. docs/mapping.md lists the same
// tables with every decision where a row departs from appendix A.
//
// Longer than 500 lines on purpose: it is data, one row per line, and
// keeping every table of appendices A and B in one file lets a reviewer read
// it side by side with the standard.
#include "mapping/mapping_table.hpp"

#include "model/vocabulary.hpp"

#include <algorithm>
#include <iterator>

namespace nclink::mapping_detail {
namespace {

constexpr double kRadToDeg = 57.29577951308232;  // 180 / pi

// ------------------------------------------------------------------ units

// Spellings of GB/T 41970 tables 10, 11 (symbols, with ASCII variants) and
// appendix A `unitType` (MTConnect names). scale/offset convert to
// mtconnect_units(dimension). UNECE codes and UnitIds follow the OPC
// Foundation's UNECE_to_OPCUA table (OPC 10000-8 5.6.3); P1 (percent) is a
// Rec. 20 code that table omits.
constexpr UnitRow kUnits[] = {
    // length
    {"mm", Dimension::length, 1, 0, "", "MMT", 5066068, "mm", "millimetre"},
    {"MILLIMETER", Dimension::length, 1, 0, "", "MMT", 5066068, "mm", "millimetre"},
    {"m", Dimension::length, 1000, 0, "x:METER", "MTR", 5067858, "m", "metre"},
    {"μm", Dimension::length, 0.001, 0, "x:MICROMETER", "4H", 13384, "µm", "micrometre (micron)"},
    {"µm", Dimension::length, 0.001, 0, "x:MICROMETER", "4H", 13384, "µm", "micrometre (micron)"},
    {"um", Dimension::length, 0.001, 0, "x:MICROMETER", "4H", 13384, "µm", "micrometre (micron)"},
    {"MILLIMETER_3D", Dimension::length_3d, 1, 0, "", "MMT", 5066068, "mm", "millimetre"},
    // velocity
    {"mm/s", Dimension::velocity, 1, 0, "", "C16", 4403510, "mm/s", "millimetre per second"},
    {"MILLIMETER/SECOND", Dimension::velocity, 1, 0, "", "C16", 4403510, "mm/s", "millimetre per second"},
    {"mm/min", Dimension::velocity, 1.0 / 60, 0, "MILLIMETER/MINUTE", "H81", 4732977, "mm/min", "millimetre per minute"},
    {"MILLIMETER/MINUTE", Dimension::velocity, 1.0 / 60, 0, "MILLIMETER/MINUTE", "H81", 4732977, "mm/min",
     "millimetre per minute"},
    {"m/min", Dimension::velocity, 1000.0 / 60, 0, "x:METER_PER_MINUTE", "2X", 12888, "m/min", "metre per minute"},
    // acceleration
    {"mm/s²", Dimension::acceleration, 1, 0, "", "M41", 5059633, "mm/s²", "millimetre per second squared"},
    {"mm/s^2", Dimension::acceleration, 1, 0, "", "M41", 5059633, "mm/s²", "millimetre per second squared"},
    {"MILLIMETER/SECOND^2", Dimension::acceleration, 1, 0, "", "M41", 5059633, "mm/s²", "millimetre per second squared"},
    // angle
    {"rad", Dimension::angle, kRadToDeg, 0, "RADIAN", "C81", 4405297, "rad", "radian"},
    {"RADIAN", Dimension::angle, kRadToDeg, 0, "RADIAN", "C81", 4405297, "rad", "radian"},
    {"DEGREE", Dimension::angle, 1, 0, "", "DD", 17476, "°", "degree [unit of angle]"},
    {"MICRO_RADIAN", Dimension::angle, kRadToDeg * 1e-6, 0, "MICRO_RADIAN", "B97", 4340023, "µrad", "microradian"},
    // angular velocity
    {"rad/s", Dimension::angular_velocity, kRadToDeg, 0, "RADIAN/SECOND", "2A", 12865, "rad/s", "radian per second"},
    {"RADIAN/SECOND", Dimension::angular_velocity, kRadToDeg, 0, "RADIAN/SECOND", "2A", 12865, "rad/s", "radian per second"},
    {"DEGREE/SECOND", Dimension::angular_velocity, 1, 0, "", "E96", 4536630, "°/s", "degree per second"},
    {"DEGREE/MINUTE", Dimension::angular_velocity, 1.0 / 60, 0, "DEGREE/MINUTE", "", 0, "°/min", "degree per minute"},
    {"RADIAN/MINUTE", Dimension::angular_velocity, kRadToDeg / 60, 0, "RADIAN/MINUTE", "", 0, "rad/min", "radian per minute"},
    // angular acceleration
    {"rad/s²", Dimension::angular_acceleration, kRadToDeg, 0, "RADIAN/SECOND^2", "2B", 12866, "rad/s²",
     "radian per second squared"},
    {"rad/s^2", Dimension::angular_acceleration, kRadToDeg, 0, "RADIAN/SECOND^2", "2B", 12866, "rad/s²",
     "radian per second squared"},
    {"RADIAN/SECOND^2", Dimension::angular_acceleration, kRadToDeg, 0, "RADIAN/SECOND^2", "2B", 12866, "rad/s²",
     "radian per second squared"},
    {"DEGREE/SECOND^2", Dimension::angular_acceleration, 1, 0, "", "M45", 5059637, "°/s²",
     "degree [unit of angle] per second squared"},
    // rotational speed
    {"r/min", Dimension::rotational_speed, 1, 0, "", "RPM", 5394509, "r/min", "revolutions per minute"},
    {"REVOLUTION/MINUTE", Dimension::rotational_speed, 1, 0, "", "RPM", 5394509, "r/min", "revolutions per minute"},
    {"REVOLUTION/SECOND", Dimension::rotational_speed, 60, 0, "REVOLUTION/SECOND", "RPS", 5394515, "r/s",
     "revolutions per second"},
    // current
    {"A", Dimension::current, 1, 0, "", "AMP", 4279632, "A", "ampere"},
    {"AMPERE", Dimension::current, 1, 0, "", "AMP", 4279632, "A", "ampere"},
    {"mA", Dimension::current, 0.001, 0, "x:MILLIAMPERE", "4K", 13387, "mA", "milliampere"},
    {"μA", Dimension::current, 1e-6, 0, "x:MICROAMPERE", "B84", 4339764, "µA", "microampere"},
    {"µA", Dimension::current, 1e-6, 0, "x:MICROAMPERE", "B84", 4339764, "µA", "microampere"},
    {"uA", Dimension::current, 1e-6, 0, "x:MICROAMPERE", "B84", 4339764, "µA", "microampere"},
    // energy
    {"kW·h", Dimension::energy, 3.6e6, 0, "KILOWATT_HOUR", "KWH", 4937544, "kW·h", "kilowatt hour"},
    {"kW.h", Dimension::energy, 3.6e6, 0, "KILOWATT_HOUR", "KWH", 4937544, "kW·h", "kilowatt hour"},
    {"KILOWATT_HOUR", Dimension::energy, 3.6e6, 0, "KILOWATT_HOUR", "KWH", 4937544, "kW·h", "kilowatt hour"},
    {"W·h", Dimension::energy, 3600, 0, "x:WATT_HOUR", "WHR", 5720146, "W·h", "watt hour"},
    {"W.h", Dimension::energy, 3600, 0, "x:WATT_HOUR", "WHR", 5720146, "W·h", "watt hour"},
    {"W·s", Dimension::energy, 1, 0, "", "J55", 4863285, "W·s", "watt second"},
    {"W.s", Dimension::energy, 1, 0, "", "J55", 4863285, "W·s", "watt second"},
    {"WATT_SECOND", Dimension::energy, 1, 0, "", "J55", 4863285, "W·s", "watt second"},
    {"JOULE", Dimension::energy, 1, 0, "JOULE", "JOU", 4869973, "J", "joule"},
    // flow and volume
    {"L/s", Dimension::flow, 1, 0, "", "G51", 4666673, "l/s", "litre per second"},
    {"LITER/SECOND", Dimension::flow, 1, 0, "", "G51", 4666673, "l/s", "litre per second"},
    {"mL/s", Dimension::flow, 0.001, 0, "x:MILLILITER_PER_SECOND", "40", 13360, "ml/s", "millilitre per second"},
    {"LITER", Dimension::volume, 1, 0, "", "LTR", 5002322, "l", "litre"},
    // frequency
    {"Hz", Dimension::frequency, 1, 0, "", "HTZ", 4740186, "Hz", "hertz"},
    {"HERTZ", Dimension::frequency, 1, 0, "", "HTZ", 4740186, "Hz", "hertz"},
    {"kHz", Dimension::frequency, 1e3, 0, "x:KILOHERTZ", "KHZ", 4933722, "kHz", "kilohertz"},
    {"MHz", Dimension::frequency, 1e6, 0, "x:MEGAHERTZ", "MHZ", 5064794, "MHz", "megahertz"},
    {"GHz", Dimension::frequency, 1e9, 0, "x:GIGAHERTZ", "A86", 4274230, "GHz", "gigahertz"},
    // mass
    {"kg", Dimension::mass, 1, 0, "", "KGM", 4933453, "kg", "kilogram"},
    {"KILOGRAM", Dimension::mass, 1, 0, "", "KGM", 4933453, "kg", "kilogram"},
    {"g", Dimension::mass, 0.001, 0, "x:GRAM", "GRM", 4674125, "g", "gram"},
    {"mg", Dimension::mass, 1e-6, 0, "x:MILLIGRAM", "MGM", 5064525, "mg", "milligram"},
    // time
    {"s", Dimension::time, 1, 0, "", "SEC", 5457219, "s", "second [unit of time]"},
    {"SECOND", Dimension::time, 1, 0, "", "SEC", 5457219, "s", "second [unit of time]"},
    // power
    {"W", Dimension::power, 1, 0, "", "WTT", 5723220, "W", "watt"},
    {"WATT", Dimension::power, 1, 0, "", "WTT", 5723220, "W", "watt"},
    {"kW", Dimension::power, 1000, 0, "KILOWATT", "KWT", 4937556, "kW", "kilowatt"},
    {"KILOWATT", Dimension::power, 1000, 0, "KILOWATT", "KWT", 4937556, "kW", "kilowatt"},
    {"mW", Dimension::power, 0.001, 0, "x:MILLIWATT", "C31", 4404017, "mW", "milliwatt"},
    // pressure
    {"Pa", Dimension::pressure, 1, 0, "", "PAL", 5259596, "Pa", "pascal"},
    {"PASCAL", Dimension::pressure, 1, 0, "", "PAL", 5259596, "Pa", "pascal"},
    // resistance
    {"Ω", Dimension::resistance, 1, 0, "", "OHM", 5195853, "Ω", "ohm"},
    {"ohm", Dimension::resistance, 1, 0, "", "OHM", 5195853, "Ω", "ohm"},
    {"OHM", Dimension::resistance, 1, 0, "", "OHM", 5195853, "Ω", "ohm"},
    {"kΩ", Dimension::resistance, 1e3, 0, "x:KILOOHM", "B49", 4338745, "kΩ", "kiloohm"},
    {"kohm", Dimension::resistance, 1e3, 0, "x:KILOOHM", "B49", 4338745, "kΩ", "kiloohm"},
    {"MΩ", Dimension::resistance, 1e6, 0, "x:MEGAOHM", "B75", 4339509, "MΩ", "megaohm"},
    {"Mohm", Dimension::resistance, 1e6, 0, "x:MEGAOHM", "B75", 4339509, "MΩ", "megaohm"},
    // temperature
    {"°C", Dimension::temperature, 1, 0, "", "CEL", 4408652, "°C", "degree Celsius"},
    {"CELSIUS", Dimension::temperature, 1, 0, "", "CEL", 4408652, "°C", "degree Celsius"},
    {"°F", Dimension::temperature, 5.0 / 9, -160.0 / 9, "FAHRENHEIT", "FAH", 4604232, "°F", "degree Fahrenheit"},
    {"FAHRENHEIT", Dimension::temperature, 5.0 / 9, -160.0 / 9, "FAHRENHEIT", "FAH", 4604232, "°F", "degree Fahrenheit"},
    // torque, force
    {"N·m", Dimension::torque, 1, 0, "", "NU", 20053, "N·m", "newton metre"},
    {"N.m", Dimension::torque, 1, 0, "", "NU", 20053, "N·m", "newton metre"},
    {"NEWTON_METER", Dimension::torque, 1, 0, "", "NU", 20053, "N·m", "newton metre"},
    {"NEWTON", Dimension::force, 1, 0, "", "NEW", 5129559, "N", "newton"},
    // viscosity
    {"Pa·s", Dimension::viscosity, 1, 0, "", "C65", 4404789, "Pa·s", "pascal second"},
    {"Pa.s", Dimension::viscosity, 1, 0, "", "C65", 4404789, "Pa·s", "pascal second"},
    {"PASCAL_SECOND", Dimension::viscosity, 1, 0, "", "C65", 4404789, "Pa·s", "pascal second"},
    {"CENTIPOISE", Dimension::viscosity, 0.001, 0, "CENTIPOISE", "C7", 17207, "cP", "centipoise"},
    // electrical
    {"VA", Dimension::apparent_power, 1, 0, "", "D46", 4469814, "V·A", "volt - ampere"},
    {"VOLT_AMPERE", Dimension::apparent_power, 1, 0, "", "D46", 4469814, "V·A", "volt - ampere"},
    {"kVA", Dimension::apparent_power, 1e3, 0, "x:KILOVOLT_AMPERE", "KVA", 4937281, "kV·A", "kilovolt - ampere"},
    {"VOLT_AMPERE_REACTIVE", Dimension::reactive_power, 1, 0, "", "D44", 4469812, "var", "var"},
    {"S/m", Dimension::conductivity, 1, 0, "", "D10", 4469040, "S/m", "siemens per metre"},
    {"SIEMENS/METER", Dimension::conductivity, 1, 0, "", "D10", 4469040, "S/m", "siemens per metre"},
    {"VOLT", Dimension::voltage, 1, 0, "", "VLT", 5655636, "V", "volt"},
    // ratios and counts. "1" is this mapping's name for a plain fraction
    // (power factor, table 10 "—"); MTConnect reports fractions in PERCENT.
    {"m/m", Dimension::ratio, 100, 0, "x:MASS_FRACTION", "C62", 4404786, "m/m", "one"},
    {"1", Dimension::ratio, 100, 0, "x:FRACTION", "C62", 4404786, "1", "one"},
    {"PERCENT", Dimension::ratio, 1, 0, "", "P1", 20529, "%", "percent"},
    {"COUNT", Dimension::count, 1, 0, "", "C62", 4404786, "1", "one"},
    // sound, pH
    {"DECIBEL", Dimension::sound, 1, 0, "", "2N", 12878, "dB", "decibel"},
    {"SOUND_LEVEL", Dimension::sound, 1, 0, "SOUND_LEVEL", "2N", 12878, "dB", "decibel"},
    {"PH", Dimension::ph, 1, 0, "", "Q30", 5321520, "pH", "pH (potential of Hydrogen)"},
};

// ------------------------------------------------------------------ values

constexpr ValuePair kStatusExecution[] = {{"running", "ACTIVE"}, {"free", "READY"}, {"holding", "FEED_HOLD"}};
constexpr ValuePair kStatusActuator[] = {{"running", "ACTIVE"}, {"free", "INACTIVE"}, {"holding", "INACTIVE"}};
constexpr ValuePair kWorkMode[] = {{"manual", "MANUAL"}, {"auto", "AUTOMATIC"}};
constexpr ValuePair kEmergency[] = {{"true", "TRIGGERED"}, {"false", "ARMED"}};
constexpr ValuePair kDoor[] = {{"true", "CLOSED"}, {"false", "OPEN"}};
constexpr ValuePair kCycleStart[] = {{"true", "ACTIVE"}, {"false", "READY"}};
constexpr ValuePair kFeedHold[] = {{"true", "FEED_HOLD"}, {"false", "READY"}};
constexpr ValuePair kOnOff[] = {{"true", "ON"}, {"false", "OFF"}};
constexpr ValuePair kActive[] = {{"true", "ACTIVE"}, {"false", "INACTIVE"}};
constexpr ValuePair kFixture[] = {{"tight", "ACTIVE"}, {"loose", "INACTIVE"}};
constexpr ValuePair kSpindleDirection[] = {{"forward", "CLOCKWISE"}, {"reverse", "COUNTER_CLOCKWISE"}, {"stop", "UNAVAILABLE"}};

// Words of table 15 (and 16 for CATAGORY), in the order that gives the
// MultiStateDiscreteType index; for two-state text items [0] is true.
constexpr std::string_view kStatusWords[] = {"running", "free", "holding"};
constexpr std::string_view kThreeWay[] = {"forward", "stop", "reverse"};
constexpr std::string_view kUserRoles[] = {"operator", "manager", "machine_manufacturer", "cnc_manufacturer", "system_manager"};
constexpr std::string_view kMachineKinds[] = {"lathe", "milling", "grinder", "planer", "other"};
constexpr std::string_view kAxisKinds[] = {"rotary", "linear"};
constexpr std::string_view kWorkModes[] = {"auto", "manual"};
constexpr std::string_view kFixtureModes[] = {"tight", "loose"};
constexpr std::string_view kToolChange[] = {"auto", "manual"};

// ------------------------------------------------------------------ row builders

template <std::size_t N>
constexpr std::size_t count_of(const ValuePair (&)[N]) {
    return N;
}
template <std::size_t N>
constexpr std::size_t count_of(const std::string_view (&)[N]) {
    return N;
}

/// A SAMPLE with units: OPC UA AnalogItemType, Double (B.8).
constexpr DataTypeRow sample(std::string_view type, std::string_view units, std::string_view mt_type, std::string_view sub_type,
                             std::string_view element, Dimension dimension, std::string_view clause,
                             Context context = Context::any) {
    return {type,
            context,
            ValueType::number,
            units,
            false,
            MtCategory::sample,
            mt_type,
            sub_type,
            element,
            MtValueForm::number,
            dimension,
            nullptr,
            0,
            clause,
            UaKind::analog,
            "Double",
            {},
            {},
            nullptr,
            0,
            std::nullopt,
            std::nullopt};
}

constexpr DataTypeRow with_range(DataTypeRow row, double low, double high) {
    row.range_low = low;
    row.range_high = high;
    return row;
}

/// A numeric EVENT in percent (overrides): AnalogItemType.
constexpr DataTypeRow override_event(std::string_view type, std::string_view mt_type, std::string_view sub_type,
                                     std::string_view element, std::string_view clause) {
    return {type,
            Context::any,
            ValueType::number,
            "PERCENT",
            false,
            MtCategory::event,
            mt_type,
            sub_type,
            element,
            MtValueForm::number,
            Dimension::ratio,
            nullptr,
            0,
            clause,
            UaKind::analog,
            "Double",
            {},
            {},
            nullptr,
            0,
            std::nullopt,
            std::nullopt};
}

/// A Boolean EVENT with an enumerated MTConnect value: TwoStateDiscreteType (B.10).
template <std::size_t N>
constexpr DataTypeRow boolean_event(std::string_view type, std::string_view mt_type, std::string_view sub_type,
                                    std::string_view element, const ValuePair (&values)[N], std::string_view clause,
                                    std::string_view true_state, std::string_view false_state) {
    return {type,
            Context::any,
            ValueType::boolean,
            "",
            false,
            MtCategory::event,
            mt_type,
            sub_type,
            element,
            MtValueForm::enumerated,
            Dimension::none,
            values,
            N,
            clause,
            UaKind::two_state,
            "Boolean",
            true_state,
            false_state,
            nullptr,
            0,
            std::nullopt,
            std::nullopt};
}

/// A text EVENT with an enumerated value; OPC UA two-state (2 words, B.10) or
/// multi-state (more, B.11) over `words`.
template <std::size_t N, std::size_t W>
constexpr DataTypeRow word_event(std::string_view type, Context context, std::string_view mt_type, std::string_view sub_type,
                                 std::string_view element, const ValuePair (&values)[N], const std::string_view (&words)[W],
                                 std::string_view clause) {
    const bool two = W == 2;
    return {type,
            context,
            ValueType::string,
            "",
            false,
            MtCategory::event,
            mt_type,
            sub_type,
            element,
            MtValueForm::enumerated,
            Dimension::none,
            values,
            N,
            clause,
            two ? UaKind::two_state : UaKind::multi_state,
            two ? "Boolean" : "UInt32",
            two ? words[0] : std::string_view{},
            two ? words[1] : std::string_view{},
            words,
            W,
            std::nullopt,
            std::nullopt};
}

/// A free-text or integer EVENT: DataItemType (B.7).
constexpr DataTypeRow text_event(std::string_view type, ValueType value_type, std::string_view mt_type, std::string_view sub_type,
                                 std::string_view element, MtValueForm form, std::string_view ua_data_type,
                                 std::string_view clause) {
    return {type,
            Context::any,
            value_type,
            "",
            false,
            MtCategory::event,
            mt_type,
            sub_type,
            element,
            form,
            Dimension::none,
            nullptr,
            0,
            clause,
            UaKind::data_item,
            ua_data_type,
            {},
            {},
            nullptr,
            0,
            std::nullopt,
            std::nullopt};
}

/// No MTConnect 1.4 type: EVENT MESSAGE, subType x:<TYPE> (fallback rule).
constexpr DataTypeRow fallback(std::string_view type, ValueType value_type, std::string_view reason,
                               std::string_view ua_data_type, Context context = Context::any) {
    return {type,
            context,
            value_type,
            "",
            true,
            MtCategory::event,
            "MESSAGE",
            "",
            "Message",
            MtValueForm::text,
            Dimension::none,
            nullptr,
            0,
            reason,
            UaKind::data_item,
            ua_data_type,
            {},
            {},
            nullptr,
            0,
            std::nullopt,
            std::nullopt};
}

/// A row whose MTConnect side falls back while its OPC UA side stays.
constexpr DataTypeRow mtconnect_fallback(DataTypeRow row, std::string_view reason) {
    row.mt_fallback = true;
    row.category = MtCategory::event;
    row.mt_type = "MESSAGE";
    row.mt_sub_type = "";
    row.element = "Message";
    row.value_form = MtValueForm::text;
    row.clause = reason;
    return row;
}

/// A fallback whose OPC UA form is a Boolean TwoStateDiscreteType.
constexpr DataTypeRow fallback_flag(std::string_view type, std::string_view reason, std::string_view true_state = "on",
                                    std::string_view false_state = "off") {
    DataTypeRow row = fallback(type, ValueType::boolean, reason, "Boolean");
    row.ua_kind = UaKind::two_state;
    row.true_state = true_state;
    row.false_state = false_state;
    return row;
}

/// A fallback whose OPC UA form is a discrete type over `words`.
template <std::size_t W>
constexpr DataTypeRow fallback_words(std::string_view type, const std::string_view (&words)[W], std::string_view reason,
                                     Context context = Context::any) {
    DataTypeRow row = fallback(type, ValueType::string, reason, W == 2 ? "Boolean" : "UInt32", context);
    row.ua_kind = W == 2 ? UaKind::two_state : UaKind::multi_state;
    if (W == 2) {
        row.true_state = words[0];
        row.false_state = words[1];
    }
    row.enum_strings = words;
    row.enum_count = W;
    return row;
}

constexpr std::string_view kModeFlag =
    "a per-mode flag: MTConnect CONTROLLER_MODE is one enumeration (A.5 0x0101), see WORK_MODE";
constexpr std::string_view kNoType = "MTConnect 1.4 has no DataItem type for it (no A.5/A.6 row)";

// ------------------------------------------------------------------ data-object types

// Context-specific rows come before the `any` row of the same type.
const DataTypeRow kRows[] = {
    // ---- table 10: physical quantities
    sample("ACCELERATION", "mm/s²", "ACCELERATION", "", "Acceleration", Dimension::acceleration,
           "MTConnect ACCELERATION (no A.5 row)"),
    sample("ANGLE", "rad", "ANGLE", "", "Angle", Dimension::angle, "A.5 0x211B, A.6 0x100D"),
    sample("ANGULAR_ACCELERATION", "rad/s²", "ANGULAR_ACCELERATION", "", "AngularAcceleration", Dimension::angular_acceleration,
           "MTConnect ANGULAR_ACCELERATION (no A.5 row)"),
    sample("ANGULAR_VELOCITY", "rad/s", "ANGULAR_VELOCITY", "", "AngularVelocity", Dimension::angular_velocity, "A.6 0x1102"),
    with_range(sample("CONCENTRATION", "m/m", "CONCENTRATION", "", "Concentration", Dimension::ratio,
                      "MTConnect CONCENTRATION (no A.5 row)"),
               0, 1),
    sample("CONDUCTIVITY", "S/m", "CONDUCTIVITY", "", "Conductivity", Dimension::conductivity,
           "MTConnect CONDUCTIVITY (no A.5 row)"),
    sample("CURRENT", "A", "AMPERAGE", "ACTUAL", "Amperage", Dimension::current, "A.6 0x100A"),
    sample("DISPLACEMENT", "mm", "DISPLACEMENT", "", "Displacement", Dimension::length, "A.5 0x5002"),
    sample("ENERGY", "kW·h", "ELECTRICAL_ENERGY", "", "ElectricalEnergy", Dimension::energy,
           "MTConnect ELECTRICAL_ENERGY (no A.5 row)"),
    sample("FLOW", "L/s", "FLOW", "", "Flow", Dimension::flow, "A.5 0x5005"),
    sample("FREQUENCY", "Hz", "FREQUENCY", "", "Frequency", Dimension::frequency, "A.5 0x3013"),
    sample("LENGTH", "mm", "LENGTH", "", "Length", Dimension::length, "A.5 0x6005"),
    // MASS is a 1.4 DataItem type, but MTConnectStreams_1.4 has no Mass
    // element to report it with: an agent could describe it and never send it.
    mtconnect_fallback(sample("MASS", "kg", "MASS", "", "Mass", Dimension::mass, ""),
                       "MTConnect 1.4 Devices lists MASS, but its Streams schema has no Mass "
                       "element"),
    sample("PERIOD", "s", "ACCUMULATED_TIME", "", "AccumulatedTime", Dimension::time, "A.5 0x5018, 0x5019"),
    sample("POSITION", "mm", "POSITION", "ACTUAL", "Position", Dimension::length, "A.5 0x2106-0x210B, 0x2112-0x2117"),
    sample("POWER", "W", "WATTAGE", "ACTUAL", "Wattage", Dimension::power, "A.5 0x5004, 0x501F"),
    with_range(
        sample("POWER_FACTOR", "1", "POWER_FACTOR", "", "PowerFactor", Dimension::ratio, "MTConnect POWER_FACTOR (no A.5 row)"),
        -1, 1),
    sample("PRESSURE", "Pa", "PRESSURE", "", "Pressure", Dimension::pressure, "A.5 0x5001"),
    sample("RESISTANCE", "Ω", "RESISTANCE", "", "Resistance", Dimension::resistance, "MTConnect RESISTANCE (no A.5 row)"),
    sample("ROTATION_SPEED", "r/min", "ROTARY_VELOCITY", "ACTUAL", "RotaryVelocity", Dimension::rotational_speed, "A.5 0x2008"),
    sample("SPEED", "mm/min", "AXIS_FEEDRATE", "ACTUAL", "AxisFeedrate", Dimension::velocity, "A.5 0x212A (axis feedrate)",
           Context::axis),
    sample("SPEED", "mm/min", "VELOCITY", "", "Velocity", Dimension::velocity, "A.6 0x1101"),
    sample("TEMPERATURE", "°C", "TEMPERATURE", "", "Temperature", Dimension::temperature, "A.5 0x5000"),
    sample("TORQUE", "N·m", "TORQUE", "", "Torque", Dimension::torque, "A.6 0x2103"),
    sample("VISCOSITY", "Pa·s", "VISCOSITY", "", "Viscosity", Dimension::viscosity, "A.5 0x5003"),
    sample("VOLT_AMPERE", "VA", "VOLT_AMPERE", "", "VoltAmpere", Dimension::apparent_power, "MTConnect VOLT_AMPERE (no A.5 row)"),

    // ---- table 12: general
    fallback_words("CATAGORY", kAxisKinds, "axis kind: a fixed value chooses Linear/Rotary (A.2 row 3); no DataItem type",
                   Context::axis_owner),
    fallback_words("CATAGORY", kMachineKinds, "machine kind (table 16): no MTConnect 1.4 DataItem type", Context::device),
    fallback("CATAGORY", ValueType::string, kNoType, "String"),
    fallback("CREATE_TIME", ValueType::string, kNoType, "String"),
    fallback("CREATOR", ValueType::string, kNoType, "String"),
    fallback("IP", ValueType::string, kNoType, "String"),
    fallback("MANUFACTURER", ValueType::string,
             "a fixed value goes to Description@manufacturer (A.1/A.3 row 3); a live one has no "
             "DataItem type",
             "String"),
    fallback("MODEL", ValueType::string,
             "a fixed value goes to Description@model (A.1/A.3 row 4); a live one has no "
             "DataItem type",
             "String"),
    fallback("NAME", ValueType::string, kNoType, "String"),
    fallback("PARAMETER", ValueType::dict, kNoType, "String"),
    text_event("SERIAL_NUMBER", ValueType::number, "SERIAL_NUMBER", "", "SerialNumber", MtValueForm::text, "String",
               "A.1/A.3 row 5 (fixed: Description@serialNumber)"),
    word_event("STATUS", Context::machine, "EXECUTION", "", "Execution", kStatusExecution, kStatusWords,
               "A.5 0x0111, 0x0112, 0x4005; A.6 0x9007"),
    word_event("STATUS", Context::any, "ACTUATOR_STATE", "", "ActuatorState", kStatusActuator, kStatusWords,
               "A.5 0x0100, 0x4004, 0x5007"),
    fallback("UPPER_LIMIT", ValueType::number, kNoType, "Double"),
    fallback_words("USER_ROLE", kUserRoles, kNoType),
    fallback("VARIABLE", ValueType::list, kNoType, "String"),
    fallback("VERSION", ValueType::string, kNoType, "String"),
    {"WARNING",
     Context::any,
     ValueType::object,
     "",
     false,
     MtCategory::condition,
     "SYSTEM",
     "",
     "",
     MtValueForm::condition,
     Dimension::none,
     nullptr,
     0,
     "A.5 0x0108, 0x010A, 0x010E",
     UaKind::data_item,
     "String",
     {},
     {},
     nullptr,
     0,
     std::nullopt,
     std::nullopt},
    word_event("WORK_MODE", Context::any, "CONTROLLER_MODE", "", "ControllerMode", kWorkMode, kWorkModes, "A.5 0x0101"),

    // ---- table 13: special
    fallback_flag("AUTO_MODE", kModeFlag),
    sample("AXIS_BACKLASH", "mm", "DISPLACEMENT", "", "Displacement", Dimension::length, "A.5 0x211E-0x2123"),
    sample("AXIS_LOAD", "kg", "LOAD", "", "Load", Dimension::ratio, "A.5 0x2124-0x2129, 0x200A"),
    fallback_flag("AXIS_TOREFPOINT", "A.5 0x0119 gives no type", "referenced", "not referenced"),
    fallback_flag("BLOCK_SKIP_MODE",
                  "A.5 0x0117 maps 程序跳段 (block skip) to SINGLE_BLOCK, another function; "
                  "MTConnect 1.4 has no block-skip subType"),
    fallback_words("CHIP_REMOVAL", kThreeWay,
                   "forward/stop/reverse fits no MTConnect 1.4 type (A.2 row 10 has only the "
                   "component)"),
    fallback("COMPACITY", ValueType::integer, kNoType, "Int32"),
    fallback("CONSOLE", ValueType::string, kNoType, "String"),
    boolean_event("COOLANT_ON", "ACTUATOR_STATE", "", "ActuatorState", kActive, "A.5 0x5007 (pump state)", "on", "off"),
    fallback("COORDINATE", ValueType::object, kNoType, "String"),
    boolean_event("CYCLE_START", "EXECUTION", "", "Execution", kCycleStart, "A.5 0x4006", "on", "off"),
    boolean_event("DOOR_CLOSED", "DOOR_STATE", "", "DoorState", kDoor, "MTConnect DOOR_STATE (no A.5 row)", "closed", "open"),
    fallback_flag("EDIT_MODE", kModeFlag),
    boolean_event("EMG", "EMERGENCY_STOP", "", "EmergencyStop", kEmergency, "A.5 0x4002", "triggered", "armed"),
    boolean_event("FEED_HOLD", "EXECUTION", "", "Execution", kFeedHold, "A.5 0x4005", "on", "off"),
    override_event("FEED_OVERRIDE", "PATH_FEEDRATE_OVERRIDE", "PROGRAMMED", "PathFeedrateOverride", "A.5 0x212E"),
    sample("FEED_SPEED", "mm/s", "PATH_FEEDRATE", "ACTUAL", "PathFeedrate", Dimension::velocity, "A.5 0x212D"),
    fallback("FILE", ValueType::file, kNoType, "String"),
    word_event("FIXTURE_MODE", Context::any, "ACTUATOR_STATE", "", "ActuatorState", kFixture, kFixtureModes, "A.5 0x7005"),
    fallback_flag("HANDLE_MODE", kModeFlag),
    fallback_flag("INCREMENTAL_MODE", kModeFlag),
    fallback_flag("JOG_MODE", kModeFlag),
    boolean_event("LIGHTING_ON", "POWER_STATE", "", "PowerState", kOnOff, "MTConnect POWER_STATE (no A.5 row)", "on", "off"),
    text_event("LINE_NUMBER", ValueType::string, "LINE_NUMBER", "ABSOLUTE", "LineNumber", MtValueForm::integer, "String",
               "A.5 0x100B"),
    boolean_event("LUBRICANT_ON", "ACTUATOR_STATE", "", "ActuatorState", kActive, "A.5 0x5011 (state of a supply system)", "on",
                  "off"),
    boolean_event("MACHINE_LOCKED", "CONTROLLER_MODE_OVERRIDE", "MACHINE_AXIS_LOCK", "ControllerModeOverride", kOnOff,
                  "A.5 0x0113 (type per MTConnect 1.4)", "on", "off"),
    fallback_flag("MDI_MODE", kModeFlag),
    fallback_flag("MST_LOCKED", "A.5 0x0114/0x4008 give EXECUTION, whose values cannot carry a lock flag"),
    boolean_event("OPT_STOP_MODE", "CONTROLLER_MODE_OVERRIDE", "OPTIONAL_STOP", "ControllerModeOverride", kOnOff,
                  "A.5 0x0116 (type per MTConnect 1.4)", "on", "off"),
    sample("PATH_LEFT_LENGTH", "mm", "LENGTH", "REMAINING", "Length", Dimension::length, "A.5 0x2118-0x211A"),
    fallback("PART", ValueType::object, kNoType, "String"),
    text_event("PART_COUNT", ValueType::string, "PART_COUNT", "ALL", "PartCount", MtValueForm::integer, "String", "A.5 0x1007"),
    text_event("PROGRAM", ValueType::string, "PROGRAM", "", "Program", MtValueForm::text, "String", "A.5 0x1000"),
    fallback("PROGRAM_MODE", ValueType::string, kNoType, "String"),
    text_event("PROGRAM_NUMBER", ValueType::integer, "PROGRAM", "", "Program", MtValueForm::text, "Int32", "A.6 0x9003"),
    override_event("RAPID_OVERRIDE", "PATH_FEEDRATE_OVERRIDE", "RAPID", "PathFeedrateOverride",
                   "A.5 0x212B (type corrected: an override, not AXIS_FEEDRATE)"),
    fallback_flag("REF_MODE", kModeFlag),
    fallback_flag("RESET_MODE", "A.5 0x4003 gives no type"),
    sample("RESIDUAL", "mm", "LENGTH", "REMAINING", "Length", Dimension::length, "A.5 0x2118-0x211D"),
    fallback("SHELF_UNIT", ValueType::list, kNoType, "String"),
    boolean_event("SINGLE_BLOCK_MODE", "CONTROLLER_MODE_OVERRIDE", "SINGLE_BLOCK", "ControllerModeOverride", kOnOff,
                  "A.5 0x0117 (type per MTConnect 1.4)", "on", "off"),
    fallback("SITE", ValueType::string, kNoType, "String"),
    word_event("SPINDLE_MODE", Context::any, "DIRECTION", "ROTARY", "Direction", kSpindleDirection, kThreeWay, "A.5 0x200B"),
    override_event("SPINDLE_OVERRIDE", "ROTARY_VELOCITY_OVERRIDE", "", "RotaryVelocityOverride",
                   "A.5 0x2009 (type per MTConnect 1.4: the spindle speed override)"),
    sample("SPINDLE_SPEED", "r/min", "ROTARY_VELOCITY", "ACTUAL", "RotaryVelocity", Dimension::rotational_speed, "A.5 0x2008"),
    text_event("SUBPROGRAM", ValueType::string, "PROGRAM", "", "Program", MtValueForm::text, "String", "A.5 0x1001"),
    fallback("TOOL", ValueType::list, "tools are MTConnect assets (A.2 row 11), not DataItems", "String"),
    fallback_words("TOOL_CHANGE", kToolChange, kNoType),
    fallback_flag("TOOL_CHANGING", kNoType),
    fallback("TOOL_PARAM", ValueType::object, "tool parameters are MTConnect assets (A.2 row 11), not DataItems", "String"),
    text_event("TOOL_NUMBER", ValueType::integer, "TOOL_NUMBER", "", "ToolNumber", MtValueForm::text, "Int32",
               "A.5 0x6003 (TOOL_NUMBER rather than TOOL_ASSET_ID)"),
    fallback("TOOL_POSITION", ValueType::integer, kNoType, "Int32"),

    // ---- appendix A `ValueTypeNames` only
    fallback("RATE", ValueType::number, "defined by no table of chapter 7", "Double"),
};

const DataTypeRow kUnknownType =
    fallback("", ValueType::any, "not a chapter-7 type: BaseDataVariableType / EVENT MESSAGE fallback", "BaseDataType");

// ------------------------------------------------------------------ components

const ComponentRow kComponents[] = {
    {"AUXILIARY", "Auxiliaries", false, UaObjectKind::component, "A.2 rows 12-14"},
    {"AXIS", "Linear", true, UaObjectKind::axes, "A.2 rows 2-3; B.3.3"},
    {"COMPONENT", "System", false, UaObjectKind::component, "A.5 d) other components to Systems"},
    {"CONTROLLER", "Controller", false, UaObjectKind::controller, "A.2 rows 1, 5; B.3.2"},
    {"FIXTURE", "Auxiliaries", false, UaObjectKind::component, "A.2 row 12"},
    {"MOTOR", "Actuator", false, UaObjectKind::actuator, "A.5 d) actuators; B.3.5"},
    {"SCREW", "System", false, UaObjectKind::component, "A.5 d) other components to Systems"},
    {"SENSOR", "Sensor", false, UaObjectKind::component, "A.2 row 13"},
    {"SERVO_DRIVER", "Actuator", false, UaObjectKind::actuator, "A.5 d) actuators; B.3.5 drives"},
    {"TOOL_MAGAZINE", "ToolingDelivery", false, UaObjectKind::component,
     "A.2 row 11 (tools are assets; the magazine delivers them)"},
};

const ComponentRow kUnknownComponent = {"", "System", false, UaObjectKind::component,
                                        "not a table-8 type: A.5 d) other components to Systems"};

bool matches(Context context, const Placement& p) {
    switch (context) {
        case Context::any: return true;
        case Context::machine: return p.on_device || p.on_controller;
        case Context::axis: return p.on_axis || p.in_axis;
        case Context::axis_owner: return p.on_axis;
        case Context::device: return p.on_device;
    }
    return false;
}

}  // namespace

std::string_view mtconnect_units(Dimension dimension) noexcept {
    switch (dimension) {
        case Dimension::none: return "";
        case Dimension::length: return "MILLIMETER";
        case Dimension::length_3d: return "MILLIMETER_3D";
        case Dimension::velocity: return "MILLIMETER/SECOND";
        case Dimension::acceleration: return "MILLIMETER/SECOND^2";
        case Dimension::angle: return "DEGREE";
        case Dimension::angular_velocity: return "DEGREE/SECOND";
        case Dimension::angular_acceleration: return "DEGREE/SECOND^2";
        case Dimension::rotational_speed: return "REVOLUTION/MINUTE";
        case Dimension::current: return "AMPERE";
        case Dimension::energy: return "WATT_SECOND";
        case Dimension::flow: return "LITER/SECOND";
        case Dimension::volume: return "LITER";
        case Dimension::frequency: return "HERTZ";
        case Dimension::mass: return "KILOGRAM";
        case Dimension::time: return "SECOND";
        case Dimension::power: return "WATT";
        case Dimension::pressure: return "PASCAL";
        case Dimension::resistance: return "OHM";
        case Dimension::temperature: return "CELSIUS";
        case Dimension::torque: return "NEWTON_METER";
        case Dimension::viscosity: return "PASCAL_SECOND";
        case Dimension::apparent_power: return "VOLT_AMPERE";
        case Dimension::reactive_power: return "VOLT_AMPERE_REACTIVE";
        case Dimension::conductivity: return "SIEMENS/METER";
        case Dimension::ratio: return "PERCENT";
        case Dimension::count: return "COUNT";
        case Dimension::voltage: return "VOLT";
        case Dimension::force: return "NEWTON";
        case Dimension::sound: return "DECIBEL";
        case Dimension::ph: return "PH";
    }
    return "";
}

const UnitRow* find_unit(std::string_view spelling) noexcept {
    for (const auto& u : kUnits)
        if (u.spelling == spelling) return &u;
    return nullptr;
}

const DataTypeRow* find_data_row(std::string_view type, const Placement& placement) noexcept {
    const DataTypeRow* any = nullptr;
    for (const auto& row : kRows) {
        if (row.type != type) continue;
        if (row.context == Context::any) {
            if (any == nullptr) any = &row;
        } else if (matches(row.context, placement)) {
            return &row;
        }
    }
    return any;
}

const DataTypeRow& unknown_type_row() noexcept { return kUnknownType; }
std::size_t data_row_count() noexcept { return std::size(kRows); }
const DataTypeRow& data_row(std::size_t index) noexcept { return kRows[index]; }

const ComponentRow* find_component_row(std::string_view type) noexcept {
    for (const auto& row : kComponents)
        if (row.type == type) return &row;
    return nullptr;
}

const ComponentRow& unknown_component_row() noexcept { return kUnknownComponent; }
std::size_t component_row_count() noexcept { return std::size(kComponents); }
const ComponentRow& component_row(std::size_t index) noexcept { return kComponents[index]; }

std::string normalize_data_type(std::string_view type) {
    if (model_detail::is_data_type(type)) return std::string(type);
    if (auto meant = model_detail::suggest_data_type(type)) return *meant;
    return std::string(type);
}

std::string normalize_component_type(std::string_view type) {
    if (model_detail::is_component_type(type)) return std::string(type);
    if (auto meant = model_detail::suggest_component_type(type)) return *meant;
    return std::string(type);
}

}  // namespace nclink::mapping_detail
