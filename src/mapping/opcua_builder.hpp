// Builds the nodes of one device namespace: GB/T 39561.3 appendix B in
// opcua_plan.cpp and, for OpcUaProfile::cnc, the OPC 40502 objects in
// cnc_profile.cpp (one class, the profile's part in its own file).
#pragma once

#include "mapping/opcua_nodes.hpp"

#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace nclink::mapping_detail {

/// How an OPC 40502 child is typed (OPC 40502 tables of CncDriveType,
/// CncAxisType, CncSpindleType, CncChannelType, CncPositionVariableType).
enum class CncSlotKind {
    analog,        ///< AnalogItemType, EngineeringUnits and EURange mandatory
    analog_range,  ///< AnalogItemType, EURange mandatory, EngineeringUnits optional
    data_item,     ///< DataItemType
    base,          ///< BaseDataVariableType
    position,      ///< CncPositionVariableType (ActPos, CmdPos, RemDist, EU, EURange)
    property,      ///< PropertyType
};

/// One child an OPC 40502 type declares (cnc_profile.cpp has the tables).
struct CncSlot {
    std::string_view name;  ///< BrowseName in the CNC namespace
    CncSlotKind kind;
    std::string_view data_type;  ///< alias: Double, Boolean, UInt32, String, NodeId, Cnc...
    int value_rank;
    std::string_view array_dimensions;
    bool mandatory;
    std::string_view matches;  ///< NC-Link types that fill it, space separated
    std::string_view derived;  ///< placeholder value from the model: see cnc_profile.cpp
};

/// An NC-Link data object that fills a slot of an OPC 40502 object.
struct CncFill {
    const CncSlot* slot = nullptr;
    const PlannedItem* item = nullptr;
    std::string path;               ///< "CncAxisType/PosDirect/ActPos"
    std::size_t parent = SIZE_MAX;  ///< node the item hangs below (set when the object is built)
    int browse_ns = 0;
};

/// The OPC 40502 role of an NC-Link component.
enum class CncRole { none, axis, spindle, channel };

class UaDeviceBuilder {
public:
    UaDeviceBuilder(UaDocument& doc, const PlannedDevice& device, int ns, int cnc_ns);
    void build();

private:
    // ---- appendix B (opcua_plan.cpp)
    void types();
    std::size_t object_type(int id, std::string_view name, std::string_view supertype, std::string_view description);
    void declaration(std::size_t type, int id, std::string_view name, UaNodeClass node_class, std::string_view reference,
                     std::string_view type_definition, std::string_view data_type, std::string_view rule);
    std::size_t device_object();
    void component(const PlannedComponent& c, std::size_t nclink_parent);
    std::size_t item(const PlannedItem& item, std::size_t owner);
    /// A property (PropertyType) below `parent`.
    std::size_t property(std::size_t parent, std::string node_id, std::string browse_name, std::string data_type, UaValue value);
    /// EngineeringUnits / EURange of an analog variable (`ns` of the browse names).
    /// EURange (mandatory, B.8) always has a value: `model_range` (the
    /// item's limits in its own unit) if given, else the quantity's range
    /// (row), else the default of the unit's dimension, else +-kNoLimit
    /// (docs/opcua.md "EURange").
    void analog_properties(std::size_t variable, const std::string& id, const UnitRow* unit, const DataTypeRow* row,
                           bool always_units, int browse_ns, std::optional<std::pair<double, double>> model_range = std::nullopt);
    /// The limits the model gives an analog item (its minimum/maximum, or an
    /// UPPER_LIMIT/LOWER_LIMIT config beside it in the same unit dimension), in its unit.
    std::optional<std::pair<double, double>> model_range(const PlannedItem& item) const;
    std::string unique_browse_name(std::size_t parent, const std::string& wanted, const std::string& fallback);
    std::string node_id(std::string_view id) const { return string_node_id(ns_, id); }

    // ---- OPC 40502 (cnc_profile.cpp)
    void cnc_prepare();
    void cnc_interface(std::size_t device_object);
    CncRole cnc_role(const PlannedComponent& c) const;
    std::size_t cnc_list(CncRole role) const;
    /// The mandatory children of a CNC object: filled slots recorded for the
    /// items, placeholders (or values derived from the model) for the rest.
    void cnc_structure(const PlannedComponent& c, CncRole role, std::size_t object);
    void cnc_slots(const PlannedComponent& c, const CncSlot* slots, std::size_t count, std::string_view type_name,
                   std::size_t object);
    std::size_t cnc_position(const PlannedComponent& c, std::string_view name, std::string_view type_name, std::size_t object);
    std::size_t cnc_placeholder(const CncSlot& slot, std::size_t parent, const std::string& id, const PlannedComponent& c);
    std::string cnc_type(std::string_view name) const;
    void cnc_match(const PlannedComponent& c, CncRole role, int channel);
    void cnc_claim(const PlannedComponent& c, const CncSlot& slot, const std::string& path, bool with_device_items);
    const PlannedItem* cnc_candidate(const PlannedComponent& c, std::string_view matches) const;
    const PlannedItem* cnc_candidate(const std::vector<PlannedItem>& items, std::string_view matches) const;
    std::string cnc_static_text(std::string_view type) const;

    UaDocument& doc_;
    const PlannedDevice& device_;
    int ns_;
    int cnc_ns_;
    std::size_t components_folder_ = 0;
    std::size_t data_items_folder_ = 0;
    std::map<std::size_t, std::set<std::string>> browse_names_;
    /// The data objects beside the items being built (their component's, or the device's).
    const std::vector<PlannedItem>* siblings_ = nullptr;
    // cnc
    std::unordered_map<const DataObject*, CncFill> fills_;
    /// (component, slot path) -> the data object filling it.
    std::map<std::pair<const Component*, std::string>, const DataObject*> slot_items_;
    std::unordered_map<const Component*, int> channel_index_;
    std::size_t axis_list_ = 0;
    std::size_t spindle_list_ = 0;
    std::size_t channel_list_ = 0;
    std::string first_channel_;
};

}  // namespace nclink::mapping_detail
