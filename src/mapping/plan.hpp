// The protocol-independent first step of both mappings: which devices, how
// every component and data object reads (normalized type, table row, unit,
// axis kind, sampling), and the notes about what was assumed.
#pragma once

#include "mapping/mapping_table.hpp"

#include <nclink/mapping.hpp>
#include <nclink/model.hpp>
#include <nclink/result.hpp>

#include <string>
#include <vector>

namespace nclink::mapping_detail {

enum class AxisKind { none, linear, rotary };

struct PlannedItem {
    const DataObject* object = nullptr;
    std::string type;                  ///< chapter-7 spelling
    bool known_type = true;            ///< in chapter 7
    const DataTypeRow* row = nullptr;  ///< never null (unknown_type_row() for unknown types)
    Placement placement;
    double sample_interval_ms = 0;  ///< smallest sampleInterval of a channel naming it; 0 = none
    /// The unit of the value: `units` if given and known, else the row's
    /// default; nullptr when there is none or `units` is unknown.
    const UnitRow* unit = nullptr;
    bool units_unknown = false;  ///< `units` given but not in the unit table
    /// True when the value is fixed in the model and a scalar (string, number, boolean).
    bool fixed_scalar() const;
};

struct PlannedComponent {
    const Component* component = nullptr;
    std::string type;                     ///< chapter-7 spelling
    bool known_type = true;               ///< in table 8
    const ComponentRow* row = nullptr;    ///< never null
    AxisKind axis_kind = AxisKind::none;  ///< AXIS only
    bool spindle = false;                 ///< AXIS only
    std::vector<PlannedItem> items;       ///< dataItems, then configs (data objects only)
    std::vector<PlannedComponent> children;
};

struct PlannedDevice {
    const Device* device = nullptr;
    std::string dev_uuid;
    std::vector<PlannedItem> items;
    std::vector<PlannedComponent> components;
};

struct Plan {
    std::vector<PlannedDevice> devices;
    std::vector<MappingNote> notes;
    /// Objects outside every device (root configs) and METHOD objects:
    /// neither document has a place for them.
    std::vector<UnmappedItem> unmapped;
};

/// Errors: see map_to_mtconnect.
Result<Plan> make_plan(const Model& model, const MappingOptions& options);

/// Text of a fixed scalar value (numbers in shortest form, booleans as
/// true/false); "" for other values.
std::string scalar_text(const Json& value);

/// Shortest round-trip text of a double ("12.5", "1E+20"), upper-case E.
std::string number_text(double value);

/// The current UTC time as xs:dateTime, or `options.creation_time`.
std::string creation_time(const MappingOptions& options);

}  // namespace nclink::mapping_detail
