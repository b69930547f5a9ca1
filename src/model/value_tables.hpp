// What chapter 7 says a value of each data object type is: its JSON shape
// (tables 10, 12, 13), the values it may take (tables 15, 16), the keys of
// its object (table 14), its physical range. Constant tables, no state; the
// compiler in value_rules.cpp turns them into one ValueRule per data object.
#pragma once

#include <nclink/value_rules.hpp>

#include <string_view>
#include <vector>

namespace nclink::model_detail {

/// One key of a table-14 object.
struct KeySpec {
    std::string_view key;
    ValueShape shape = ValueShape::any;
    bool required = false;
};

/// The keys of one table-14 object (or of a FILE object). Keys not listed
/// are allowed: the standard lets users add their own (key_value and beyond).
struct ObjectSpec {
    std::string_view name;  ///< "COORDINATE", "WARNING", "FILE", ...
    std::vector<KeySpec> keys;
    /// COORDINATE: keys of the form x, y, z, a, b, c, u, v, w, optionally
    /// followed by a number (x1 ... xn), are axis values (numbers).
    bool axis_keys = false;
};

/// A data object type's value as chapter 7 gives it.
struct TypeSpec {
    ValueShape shape = ValueShape::any;
    std::string_view where;                     ///< the table that says so, for messages
    std::vector<std::string_view> enumeration;  ///< table 15 (empty = any string)
    std::vector<std::int64_t> int_enumeration;  ///< appendix A's STATUS 0/1/2
    bool has_min = false;
    double min = 0;
    bool has_max = false;
    double max = 0;
    const ObjectSpec* object = nullptr;
    /// TEMPERATURE: the lower bound depends on the units (absolute zero).
    bool temperature = false;
};

/// The spec of a type of tables 10, 12, 13; nullptr for any other type.
const TypeSpec* type_spec(std::string_view type) noexcept;

/// The FILE object (FILE items, PART snap_shot/geometry_file).
const ObjectSpec& file_object() noexcept;

/// Table 16: the values a CATAGORY may take under a component/device of
/// `parent_type`; empty when table 16 gives none for that parent.
const std::vector<std::string_view>& catagory_values(std::string_view parent_type) noexcept;

/// Absolute zero in `units` (table 10 default °C; °F; K), for TEMPERATURE.
double absolute_zero(std::string_view units) noexcept;

/// True for a COORDINATE axis key: one of x y z a b c u v w (either case),
/// optionally followed by decimal digits (x1 ... xn, table 14).
bool is_axis_key(std::string_view key) noexcept;

}  // namespace nclink::model_detail
