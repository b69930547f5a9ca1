// The mapping tables: every NC-Link component type (GB/T 41970-2022 table 8)
// and data-object type (tables 10, 12, 13) with its MTConnect 1.4 form
// (GB/T 39561.3 appendix A) and its OPC UA form (appendix B), and every unit
// of tables 10, 11 and appendix A with its MTConnect name and UNECE code.
// Constant data; the rules that pick a row live in mapping_table.cpp too, so
// this is the one place to read or change what maps to what.
#pragma once

#include <nclink/mapping.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace nclink::mapping_detail {

/// What a unit measures; each has one MTConnect unit that values are converted to.
enum class Dimension {
    none,
    length,
    length_3d,
    velocity,
    acceleration,
    angle,
    angular_velocity,
    angular_acceleration,
    rotational_speed,
    current,
    energy,
    flow,
    volume,
    frequency,
    mass,
    time,
    power,
    pressure,
    resistance,
    temperature,
    torque,
    viscosity,
    apparent_power,
    reactive_power,
    conductivity,
    ratio,
    count,
    voltage,
    force,
    sound,
    ph,
};

/// The MTConnect units every value of a dimension is reported in ("" for none).
std::string_view mtconnect_units(Dimension dimension) noexcept;

/// One NC-Link unit spelling.
struct UnitRow {
    std::string_view spelling;  ///< as written in `units` (tables 10, 11, appendix A)
    Dimension dimension;
    double scale;  ///< to mtconnect_units(dimension): v * scale + offset
    double offset;
    std::string_view native_units;  ///< MTConnect nativeUnits ("" = same as units)
    std::string_view unece;         ///< UN/CEFACT Rec. 20 common code ("" = none)
    std::int32_t unit_id;           ///< OPC UA EUInformation.UnitId (OPC 10000-8 5.6.3)
    std::string_view display;       ///< EUInformation.DisplayName
    std::string_view description;   ///< EUInformation.Description
};

/// The row of a unit spelling; nullptr when unknown.
const UnitRow* find_unit(std::string_view spelling) noexcept;

/// JSON type of a data object's value (tables 10, 12, 13 "value 属性数据类型").
enum class ValueType { number, integer, string, boolean, object, list, dict, file, any };

/// Where a data object sits; some types map differently by owner.
enum class Context {
    any,
    machine,     ///< owned by the device or a CONTROLLER
    axis,        ///< owned by an AXIS or a component inside one
    axis_owner,  ///< owned directly by an AXIS (CATAGORY: linear/rotary)
    device,      ///< owned directly by the device (CATAGORY: lathe, milling, ...)
};

/// OPC UA variable type of a row (appendix B tables B.7-B.11).
enum class UaKind {
    data_item,    ///< DataItemType (B.7)
    analog,       ///< AnalogItemType (B.8)
    two_state,    ///< TwoStateDiscreteType (B.10)
    multi_state,  ///< MultiStateDiscreteType (B.11)
};

/// An NC-Link value word and the MTConnect value it becomes.
struct ValuePair {
    std::string_view nclink;
    std::string_view mtconnect;
};

/// One data-object type in one context.
struct DataTypeRow {
    std::string_view type;
    Context context;
    ValueType value_type;
    std::string_view default_units;  ///< table 10/13 "数据单位" ("" = none)
    // MTConnect (appendix A, tables A.4-A.6)
    bool mt_fallback;  ///< no 1.4 type: EVENT MESSAGE, subType x:<TYPE>
    MtCategory category;
    std::string_view mt_type;
    std::string_view mt_sub_type;
    std::string_view element;  ///< Streams element
    MtValueForm value_form;
    Dimension dimension;      ///< what the value measures (number forms)
    const ValuePair* values;  ///< enumerated: NC-Link word -> MTConnect value
    std::size_t value_count;
    std::string_view clause;  ///< the appendix A row it follows, or why it falls back
    // OPC UA (appendix B)
    UaKind ua_kind;
    std::string_view ua_data_type;  ///< "Double", "Int32", "Boolean", "String"
    std::string_view true_state;    ///< two_state: TrueState text (and, for text items, the true word)
    std::string_view false_state;
    const std::string_view* enum_strings;  ///< multi_state / text two_state: the NC-Link words
    std::size_t enum_count;
    std::optional<double> range_low;  ///< EURange where the quantity has one
    std::optional<double> range_high;
};

/// Where a data object sits, as the contexts of the rows ask it.
struct Placement {
    bool on_device = false;      ///< in the device's own dataItems/configs
    bool on_controller = false;  ///< in a CONTROLLER's
    bool on_axis = false;        ///< in an AXIS's own
    bool in_axis = false;        ///< in a component below an AXIS
};

/// The row for a (chapter-7 spelt) type where it sits: a context-specific row
/// first, else the `any` row; nullptr when the type is not in chapter 7.
const DataTypeRow* find_data_row(std::string_view type, const Placement& placement) noexcept;

/// The fallback used for types chapter 7 does not define.
const DataTypeRow& unknown_type_row() noexcept;

/// Every row, for documentation and tests.
std::size_t data_row_count() noexcept;
const DataTypeRow& data_row(std::size_t index) noexcept;

/// OPC UA object types of the device namespace (appendix B tables B.1-B.6).
enum class UaObjectKind { device, component, controller, axes, door, actuator };

/// One component type of table 8.
struct ComponentRow {
    std::string_view type;
    std::string_view element;  ///< MTConnect element; AXIS: "Linear", resolved per axis
    bool in_axes;              ///< grouped under an Axes container (table A.2)
    UaObjectKind ua_kind;
    std::string_view clause;
};

/// The row of a table-8 component type; nullptr for other types.
const ComponentRow* find_component_row(std::string_view type) noexcept;
/// Unknown component types: System (A.5 "other components to Systems").
const ComponentRow& unknown_component_row() noexcept;
std::size_t component_row_count() noexcept;
const ComponentRow& component_row(std::size_t index) noexcept;

/// Chapter-7 spelling of a type as written (TYPE -> CATAGORY, lower case,
/// SPDL_OVERRIDE ...), or the type itself.
std::string normalize_data_type(std::string_view type);
std::string normalize_component_type(std::string_view type);

}  // namespace nclink::mapping_detail
