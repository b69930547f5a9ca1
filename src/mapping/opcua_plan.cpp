// plan_opcua: GB/T 39561.3 appendix B applied to a Plan. One namespace per
// device (urn:nclink:device:<dev_uuid>) holding the object types of tables
// B.1-B.6 and the instances: the device (B.2), its components (B.3) and a
// variable per data object typed by tables B.7-B.11.
//
// Longer than 500 lines on purpose: UaDeviceBuilder walks one device in one
// pass (types, device object, components, items) and each step uses the node
// list and the value forms defined above it; split, those would need an
// internal header of their own for this file's sake only.
#include "mapping/opcua_builder.hpp"

#include "mapping/names.hpp"

#include <fmt/format.h>

#include <cmath>

namespace nclink::mapping_detail {

// ------------------------------------------------------------------ node list

std::string string_node_id(int ns, std::string_view id) { return fmt::format("ns={};s={}", ns, id); }
std::string numeric_node_id(int ns, int id) { return fmt::format("ns={};i={}", ns, id); }
std::string qualified(int ns, std::string_view name) { return fmt::format("{}:{}", ns, name); }

std::size_t UaNodeList::add(UaNode node) {
    const std::size_t index = nodes_.size();
    if (!index_.emplace(node.node_id, index).second && collision_.empty()) collision_ = node.node_id;
    nodes_.push_back(std::move(node));
    return index;
}

void UaNodeList::link(std::size_t source, std::size_t target, std::string_view type) {
    nodes_[source].references.push_back(UaReference{std::string(type), nodes_[target].node_id, true});
    nodes_[target].references.push_back(UaReference{std::string(type), nodes_[source].node_id, false});
    const bool hierarchical = type == "HasComponent" || type == "HasProperty" || type == "Organizes";
    if (hierarchical && nodes_[target].parent.empty() && nodes_[target].node_class != UaNodeClass::object_type)
        nodes_[target].parent = nodes_[source].node_id;
}

void UaNodeList::reference(std::size_t source, std::string_view type, std::string target, bool forward) {
    nodes_[source].references.push_back(UaReference{std::string(type), std::move(target), forward});
}

namespace {

// Object types of the device namespace (numeric ids never clash with the
// string ids of instances).
constexpr int kDeviceType = 1001;
constexpr int kComponentType = 1002;
constexpr int kControllerType = 1003;
constexpr int kAxesType = 1004;
constexpr int kDoorType = 1005;
constexpr int kActuatorType = 1006;

int object_type_id(UaObjectKind kind) {
    switch (kind) {
        case UaObjectKind::device: return kDeviceType;
        case UaObjectKind::component: return kComponentType;
        case UaObjectKind::controller: return kControllerType;
        case UaObjectKind::axes: return kAxesType;
        case UaObjectKind::door: return kDoorType;
        case UaObjectKind::actuator: return kActuatorType;
    }
    return kComponentType;
}

std::string_view type_definition_name(UaKind kind) {
    switch (kind) {
        case UaKind::analog: return "AnalogItemType";
        case UaKind::two_state: return "TwoStateDiscreteType";
        case UaKind::multi_state: return "MultiStateDiscreteType";
        case UaKind::data_item: return "DataItemType";
    }
    return "DataItemType";
}

std::string_view type_definition_id(std::string_view name) {
    if (name == "AnalogItemType") return ua::analog_item_type;
    if (name == "TwoStateDiscreteType") return ua::two_state_type;
    if (name == "MultiStateDiscreteType") return ua::multi_state_type;
    if (name == "BaseDataVariableType") return ua::base_data_variable_type;
    return ua::data_item_type;
}

UaValue string_value(std::string text) {
    UaValue v;
    v.kind = UaValue::Kind::string;
    v.text = std::move(text);
    return v;
}

UaValue localized(std::string text) {
    UaValue v;
    v.kind = UaValue::Kind::localized;
    v.text = std::move(text);
    return v;
}

std::string json_text(const Json& value) { return value.dump(-1, ' ', false, Json::error_handler_t::replace); }

/// The fixed value of a data object in the variable's DataType; kind none
/// when there is no fixed value or it does not convert.
UaValue fixed_value(const DataObject& d, const UaVariable& v) {
    UaValue out;
    if (!d.value || d.value->is_null()) return out;
    const Json& j = *d.value;
    switch (v.encoding) {
        case UaEncoding::json: return string_value(json_text(j));
        case UaEncoding::enum_index:
            if (j.is_string())
                for (std::size_t i = 0; i < v.enum_strings.size(); ++i)
                    if (v.enum_strings[i] == j.get<std::string>()) {
                        out.kind = UaValue::Kind::uint32;
                        out.integer = static_cast<long long>(i);
                    }
            return out;
        case UaEncoding::two_state:
            if (j.is_boolean()) {
                out.kind = UaValue::Kind::boolean;
                out.flag = j.get<bool>();
            } else if (j.is_string() && !v.true_value.empty()) {
                const auto& word = j.get_ref<const std::string&>();
                if (word == v.true_value || word == v.false_value) {
                    out.kind = UaValue::Kind::boolean;
                    out.flag = word == v.true_value;
                }
            }
            return out;
        case UaEncoding::scalar: break;
    }
    if (v.data_type == "Double" && j.is_number()) {
        out.kind = UaValue::Kind::number;
        out.number = j.get<double>();
    } else if ((v.data_type == "Int32" || v.data_type == "UInt32") && j.is_number()) {
        const double n = j.get<double>();
        const bool is_unsigned = v.data_type == "UInt32";
        if (std::floor(n) == n && n >= (is_unsigned ? 0.0 : -2147483648.0) && n <= (is_unsigned ? 4294967295.0 : 2147483647.0)) {
            out.kind = is_unsigned ? UaValue::Kind::uint32 : UaValue::Kind::int32;
            out.integer = static_cast<long long>(n);
        }
    } else if (v.data_type == "Boolean" && j.is_boolean()) {
        out.kind = UaValue::Kind::boolean;
        out.flag = j.get<bool>();
    } else if (v.data_type == "String") {
        out = string_value(j.is_string() ? j.get<std::string>() : (j.is_primitive() ? scalar_text(j) : json_text(j)));
    } else if (v.data_type == "BaseDataType") {
        if (j.is_boolean()) {
            out.kind = UaValue::Kind::boolean;
            out.flag = j.get<bool>();
        } else if (j.is_number()) {
            out.kind = UaValue::Kind::number;
            out.number = j.get<double>();
        } else {
            out = string_value(j.is_string() ? j.get<std::string>() : json_text(j));
        }
    }
    return out;
}

std::string dev_name(const Device& d) { return d.name.empty() ? d.id : d.name; }

/// EURange of a quantity with no range of its own and none in the model, in
/// MTConnect units (docs/opcua.md "EURange"): wider than any machine tool
/// reaches, so a value outside means a fault, not a bigger machine.
std::optional<std::pair<double, double>> default_range(Dimension dimension) {
    switch (dimension) {
        case Dimension::length: return std::make_pair(-10000.0, 10000.0);              // mm: 10 m each way
        case Dimension::velocity: return std::make_pair(-10000.0, 10000.0);            // mm/s: 600 m/min
        case Dimension::acceleration: return std::make_pair(-100000.0, 100000.0);      // mm/s^2: 10 g
        case Dimension::angle: return std::make_pair(-3600.0, 3600.0);                 // degrees: ten turns
        case Dimension::angular_velocity: return std::make_pair(-600000.0, 600000.0);  // deg/s: 100000 r/min
        case Dimension::rotational_speed: return std::make_pair(-100000.0, 100000.0);  // r/min
        case Dimension::current: return std::make_pair(-1000.0, 1000.0);               // A
        case Dimension::voltage: return std::make_pair(-1000.0, 1000.0);               // V
        case Dimension::ratio: return std::make_pair(0.0, 200.0);                      // percent: loads, overrides
        case Dimension::temperature: return std::make_pair(-50.0, 500.0);              // degrees Celsius
        default: return std::nullopt;
    }
}

/// A quantity with no range anywhere: +-1e9 of its unit (no limit known).
constexpr double kNoLimit = 1e9;

/// A value in MTConnect units as a value in `unit` (MTConnect = v * scale + offset).
double in_unit(double common, const UnitRow* unit) {
    if (unit == nullptr || unit->scale == 0) return common;
    return (common - unit->offset) / unit->scale;
}

}  // namespace

// ------------------------------------------------------------------ device builder

UaDeviceBuilder::UaDeviceBuilder(UaDocument& doc, const PlannedDevice& device, int ns, int cnc_ns)
    : doc_(doc), device_(device), ns_(ns), cnc_ns_(cnc_ns) {}

void UaDeviceBuilder::build() {
    types();
    if (cnc_ns_ != 0) cnc_prepare();
    const std::size_t device = device_object();
    if (cnc_ns_ != 0) cnc_interface(device);
    for (const auto& c : device_.components) component(c, components_folder_);
    // Device-level items last: a CNC channel object they fill exists by now.
    siblings_ = &device_.items;
    for (const auto& i : device_.items) item(i, data_items_folder_);
}

std::size_t UaDeviceBuilder::object_type(int id, std::string_view name, std::string_view supertype, std::string_view description) {
    UaNode n;
    n.node_class = UaNodeClass::object_type;
    n.node_id = numeric_node_id(ns_, id);
    n.browse_name = qualified(ns_, name);
    n.display_name = std::string(name);
    n.description = std::string(description);
    const std::size_t index = doc_.nodes.add(std::move(n));
    doc_.nodes.reference(index, "HasSubtype", std::string(supertype), false);
    return index;
}

void UaDeviceBuilder::declaration(std::size_t type, int id, std::string_view name, UaNodeClass node_class,
                                  std::string_view reference, std::string_view type_definition, std::string_view data_type,
                                  std::string_view rule) {
    UaNode n;
    n.node_class = node_class;
    n.node_id = numeric_node_id(ns_, id);
    n.browse_name = qualified(ns_, name);
    n.display_name = std::string(name);
    n.data_type = std::string(data_type);
    const std::size_t index = doc_.nodes.add(std::move(n));
    doc_.nodes.link(type, index, reference);
    doc_.nodes.reference(index, "HasTypeDefinition", std::string(type_definition), true);
    doc_.nodes.reference(index, "HasModellingRule", std::string(rule), true);
}

/// Tables B.1-B.6. The supertypes follow the clause texts where the tables
/// name types that do not exist (B.2 "MTDeviceType", B.5/B.6 "MTDDeviceType").
void UaDeviceBuilder::types() {
    const auto V = UaNodeClass::variable;
    const auto O = UaNodeClass::object;
    const std::size_t device =
        object_type(kDeviceType, "DeviceType", ua::folder_type, "GB/T 39561.3 table B.1: a numerically controlled device");
    declaration(device, 1101, "Availability", V, "HasComponent", ua::data_item_type, "String", ua::mandatory);
    declaration(device, 1102, "Manufacturer", V, "HasProperty", ua::property_type, "String", ua::mandatory);
    declaration(device, 1103, "SerialNumber", V, "HasProperty", ua::property_type, "String", ua::mandatory);
    declaration(device, 1104, "Configuration", V, "HasProperty", ua::property_type, "String", ua::optional);
    declaration(device, 1105, "SampleInterval", V, "HasProperty", ua::property_type, "Duration", ua::optional);
    declaration(device, 1106, "DataItems", O, "HasComponent", ua::folder_type, "", ua::mandatory);
    declaration(device, 1107, "Components", O, "HasComponent", ua::folder_type, "", ua::mandatory);
    declaration(device, 1108, "Conditions", O, "HasComponent", ua::folder_type, "", ua::optional);

    const std::size_t component =
        object_type(kComponentType, "ComponentType", ua::folder_type, "GB/T 39561.3 table B.2: a component of a device");
    declaration(component, 1111, "Model", V, "HasProperty", ua::property_type, "String", ua::optional);
    declaration(component, 1112, "Station", V, "HasProperty", ua::property_type, "String", ua::optional);

    const std::string base = numeric_node_id(ns_, kComponentType);
    object_type(kControllerType, "ControllerType", base, "GB/T 39561.3 table B.3: a controller");
    const std::size_t axes = object_type(kAxesType, "AxesType", base, "GB/T 39561.3 table B.4: a linear or rotary axis");
    int id = 1131;
    for (const char* name : {"RotaryAxesX", "RotaryAxesY", "RotaryAxesZ", "RotaryAxesA", "RotaryAxesB", "RotaryAxesC"})
        declaration(axes, id++, name, V, "HasProperty", ua::property_type, "String", ua::optional);
    const std::size_t door = object_type(kDoorType, "DoorType", base, "GB/T 39561.3 table B.5: a door");
    declaration(door, 1121, "DoorState", V, "HasProperty", ua::property_type, "String", ua::optional);
    const std::size_t actuator = object_type(kActuatorType, "ActuatorType", base, "GB/T 39561.3 table B.6: a drive or actuator");
    declaration(actuator, 1141, "LinearAxesX", V, "HasProperty", ua::property_type, "String", ua::optional);
    // B.3.1-B.3.5 derive each from its parent; link the subtypes both ways.
    for (const int sub : {kControllerType, kAxesType, kDoorType, kActuatorType})
        doc_.nodes.reference(component, "HasSubtype", numeric_node_id(ns_, sub), true);
}

std::size_t UaDeviceBuilder::property(std::size_t parent, std::string node_id, std::string browse_name, std::string data_type,
                                      UaValue value) {
    UaNode n;
    n.node_class = UaNodeClass::variable;
    n.node_id = std::move(node_id);
    n.display_name = browse_name.substr(browse_name.find(':') + 1);
    n.browse_name = std::move(browse_name);
    n.data_type = std::move(data_type);
    n.value = std::move(value);
    if (n.value.kind == UaValue::Kind::localized_list) {
        n.value_rank = 1;
        n.array_dimensions = std::to_string(n.value.list.size());
    }
    const std::size_t index = doc_.nodes.add(std::move(n));
    doc_.nodes.link(parent, index, "HasProperty");
    doc_.nodes.reference(index, "HasTypeDefinition", std::string(ua::property_type), true);
    return index;
}

std::size_t UaDeviceBuilder::device_object() {
    const Device& d = *device_.device;
    UaNode n;
    n.node_id = node_id(device_.dev_uuid);
    n.browse_name = qualified(ns_, dev_name(d));
    n.display_name = dev_name(d);
    n.description = d.description;
    const std::size_t device = doc_.nodes.add(std::move(n));
    doc_.nodes.reference(device, "HasTypeDefinition", numeric_node_id(ns_, kDeviceType), true);
    doc_.nodes.reference(device, "Organizes", std::string(ua::objects_folder), false);

    // Table B.1 mandatory children.
    UaNode avail;
    avail.node_class = UaNodeClass::variable;
    avail.node_id = node_id(device_.dev_uuid + ".Availability");
    avail.browse_name = qualified(ns_, "Availability");
    avail.display_name = "Availability";
    avail.description = "AVAILABLE while the device's adapter is online, else UNAVAILABLE";
    avail.data_type = "String";
    const std::size_t a = doc_.nodes.add(std::move(avail));
    doc_.nodes.link(device, a, "HasComponent");
    doc_.nodes.reference(a, "HasTypeDefinition", std::string(ua::data_item_type), true);
    browse_names_[device].insert(qualified(ns_, "Availability"));

    std::string manufacturer, serial;
    for (const auto& i : device_.items) {
        if (!i.fixed_scalar()) continue;
        if (i.type == "MANUFACTURER" && manufacturer.empty()) manufacturer = scalar_text(*i.object->value);
        if (i.type == "SERIAL_NUMBER" && serial.empty()) serial = scalar_text(*i.object->value);
    }
    property(device, node_id(device_.dev_uuid + ".Manufacturer"), qualified(ns_, "Manufacturer"), "String",
             string_value(manufacturer));
    property(device, node_id(device_.dev_uuid + ".SerialNumber"), qualified(ns_, "SerialNumber"), "String", string_value(serial));
    browse_names_[device].insert({qualified(ns_, "Manufacturer"), qualified(ns_, "SerialNumber")});

    for (const auto& [name, out] :
         {std::pair<const char*, std::size_t*>{"DataItems", &data_items_folder_}, {"Components", &components_folder_}}) {
        UaNode f;
        f.node_id = node_id(device_.dev_uuid + "." + name);
        f.browse_name = qualified(ns_, name);
        f.display_name = name;
        *out = doc_.nodes.add(std::move(f));
        doc_.nodes.link(device, *out, "HasComponent");
        doc_.nodes.reference(*out, "HasTypeDefinition", std::string(ua::folder_type), true);
        browse_names_[device].insert(qualified(ns_, name));
    }
    return device;
}

void UaDeviceBuilder::component(const PlannedComponent& c, std::size_t nclink_parent) {
    const Component& comp = *c.component;
    const CncRole role = cnc_ns_ != 0 ? cnc_role(c) : CncRole::none;
    const std::size_t parent = role == CncRole::none ? nclink_parent : cnc_list(role);
    UaNode n;
    n.node_id = node_id(comp.id);
    n.browse_name = unique_browse_name(parent, comp.name.empty() ? comp.id : comp.name, comp.id);
    n.display_name = comp.name.empty() ? comp.id : comp.name;
    n.description = comp.description;
    n.extension = {{"id", comp.id}, {"type", comp.type}};
    const std::size_t object = doc_.nodes.add(std::move(n));
    doc_.nodes.link(parent, object, "HasComponent");
    if (role != CncRole::none) {
        doc_.nodes.link(nclink_parent, object, "Organizes");
        doc_.nodes.reference(object, "HasTypeDefinition",
                             cnc_type(role == CncRole::axis      ? "CncAxisType"
                                      : role == CncRole::spindle ? "CncSpindleType"
                                                                 : "CncChannelType"),
                             true);
        cnc_structure(c, role, object);
    } else {
        doc_.nodes.reference(object, "HasTypeDefinition", numeric_node_id(ns_, object_type_id(c.row->ua_kind)), true);
    }
    if (!c.known_type) doc_.unmapped.push_back(UnmappedItem{comp.id, comp.type, "ComponentType", std::string(c.row->clause)});
    siblings_ = &c.items;
    for (const auto& i : c.items) item(i, object);
    for (const auto& child : c.children) component(child, object);
}

std::size_t UaDeviceBuilder::item(const PlannedItem& planned, std::size_t owner) {
    const DataObject& d = *planned.object;
    const DataTypeRow& row = *planned.row;
    const auto fill = fills_.find(&d);
    const CncFill* cnc = fill == fills_.end() ? nullptr : &fill->second;
    const std::size_t parent = cnc != nullptr ? cnc->parent : owner;

    UaVariable v;
    v.item_id = d.id;
    v.nclink_type = planned.type;
    v.node_id = node_id(d.id);
    v.namespace_uri = OpcUaMappingBuilder::namespaces(doc_.mapping)[ns_ - 1].uri;
    v.access_level = d.setable ? 3 : 1;
    v.minimum_sampling_interval = planned.sample_interval_ms;
    const bool json = d.kind != DataKind::single || row.value_type == ValueType::object || row.value_type == ValueType::list ||
                      row.value_type == ValueType::dict || row.value_type == ValueType::file;
    int value_rank = -1;
    if (!planned.known_type) {
        v.fallback = true;
        v.type_definition = "BaseDataVariableType";
        v.data_type = "BaseDataType";
        value_rank = -2;
        doc_.unmapped.push_back(UnmappedItem{d.id, d.type, "BaseDataVariableType (BaseDataType)", std::string(row.clause)});
    } else if (json) {
        v.type_definition = "DataItemType";
        v.data_type = "String";
        v.encoding = UaEncoding::json;
    } else if (planned.fixed_scalar() && d.value->is_string() &&
               (row.ua_kind == UaKind::two_state || row.ua_kind == UaKind::multi_state)) {
        // A word the model fixes (a CATAGORY "milling" or "linear", a fixed
        // TOOL_CHANGE "auto") never changes, so a discrete type's index or
        // flag only hides it: a client reading the variable must see the
        // word (B.7 DataItemType, String), as the model states it.
        v.type_definition = "DataItemType";
        v.data_type = "String";
    } else {
        v.type_definition = std::string(type_definition_name(row.ua_kind));
        v.data_type = std::string(row.ua_data_type);
        if (row.ua_kind == UaKind::two_state) {
            v.encoding = UaEncoding::two_state;
            if (row.value_type == ValueType::string) {
                v.true_value = std::string(row.true_state);
                v.false_value = std::string(row.false_state);
            }
        } else if (row.ua_kind == UaKind::multi_state) {
            v.encoding = UaEncoding::enum_index;
            for (std::size_t i = 0; i < row.enum_count; ++i) v.enum_strings.emplace_back(row.enum_strings[i]);
        }
    }
    if (cnc != nullptr) {
        v.cnc_slot = cnc->path;
        if (cnc->slot->kind == CncSlotKind::data_item) v.data_type = std::string(cnc->slot->data_type);
        v.browse_name = std::string(cnc->slot->name);
    }

    UaNode n;
    n.node_class = UaNodeClass::variable;
    n.node_id = v.node_id;
    const std::string label = d.name.empty() ? d.id : d.name;
    n.browse_name = cnc != nullptr ? qualified(cnc->browse_ns, cnc->slot->name) : unique_browse_name(parent, label, d.id);
    if (cnc == nullptr) v.browse_name = n.browse_name.substr(n.browse_name.find(':') + 1);
    n.display_name = cnc != nullptr ? std::string(cnc->slot->name) : label;
    n.description = d.description;
    n.data_type = v.data_type;
    n.value_rank = value_rank;
    n.access_level = v.access_level;
    n.minimum_sampling_interval = v.minimum_sampling_interval;
    n.value = fixed_value(d, v);
    if (d.value && !d.value->is_null() && n.value.kind == UaValue::Kind::none)
        doc_.notes.push_back(MappingNote{d.id, fmt::format("fixed value {} does not fit DataType "
                                                           "{}: left out of the NodeSet",
                                                           json_text(*d.value), v.data_type)});
    n.extension = {{"id", d.id},
                   {"type", planned.type},
                   {"datatype", std::string(to_string(d.kind))},
                   {"setable", d.setable ? "true" : "false"},
                   {"encoding", std::string(to_string(v.encoding))}};
    const std::size_t index = doc_.nodes.add(std::move(n));
    doc_.nodes.link(parent, index, "HasComponent");
    if (parent != owner) doc_.nodes.link(owner, index, "Organizes");
    doc_.nodes.reference(index, "HasTypeDefinition", std::string(type_definition_id(v.type_definition)), true);

    // Properties of tables B.8, B.10, B.11.
    if (v.type_definition == "AnalogItemType") {
        const bool slot_units = cnc != nullptr && cnc->slot->kind == CncSlotKind::analog;
        analog_properties(index, d.id, planned.unit, &row, slot_units, 0, model_range(planned));
    } else if (v.type_definition == "TwoStateDiscreteType") {
        property(index, node_id(d.id + ".TrueState"), "TrueState", "LocalizedText",
                 localized(std::string(row.true_state.empty() ? "true" : row.true_state)));
        property(index, node_id(d.id + ".FalseState"), "FalseState", "LocalizedText",
                 localized(std::string(row.false_state.empty() ? "false" : row.false_state)));
    } else if (v.type_definition == "MultiStateDiscreteType") {
        UaValue list;
        list.kind = UaValue::Kind::localized_list;
        list.list = v.enum_strings;
        property(index, node_id(d.id + ".EnumStrings"), "EnumStrings", "LocalizedText", std::move(list));
    }
    // Table B.7: SampleInterval (Duration, ms) of a variable a SAMPLE_CHANNEL
    // lists, its channel's sampleInterval (the shortest, when several list it).
    if (planned.sample_interval_ms > 0) {
        UaValue interval;
        interval.kind = UaValue::Kind::number;
        interval.number = planned.sample_interval_ms;
        property(index, node_id(d.id + ".SampleInterval"), qualified(ns_, "SampleInterval"), "Duration", interval);
    }
    OpcUaMappingBuilder::variables(doc_.mapping).push_back(std::move(v));
    return index;
}

void UaDeviceBuilder::analog_properties(std::size_t variable, const std::string& id, const UnitRow* unit, const DataTypeRow* row,
                                        bool always_units, int browse_ns, std::optional<std::pair<double, double>> model_range) {
    const auto browse = [&](const char* name) { return browse_ns == 0 ? std::string(name) : qualified(browse_ns, name); };
    if (unit != nullptr && !unit->unece.empty()) {
        UaValue eu;
        eu.kind = UaValue::Kind::eu_information;
        eu.unit = unit;
        property(variable, node_id(id + ".EngineeringUnits"), browse("EngineeringUnits"), "EUInformation", eu);
    } else if (always_units) {
        property(variable, node_id(id + ".EngineeringUnits"), browse("EngineeringUnits"), "EUInformation", UaValue{});
    }
    // EURange is mandatory (table B.8) and a client scales and deadbands with
    // it (OPC 10000-8 5.3.2.2 PercentDeadband), so it always has a value.
    UaValue range;
    range.kind = UaValue::Kind::range;
    if (model_range) {
        range.low = model_range->first;
        range.high = model_range->second;
    } else if (row != nullptr && row->range_low && row->range_high) {
        range.low = *row->range_low;
        range.high = *row->range_high;
    } else {
        const Dimension dimension = unit != nullptr ? unit->dimension : row != nullptr ? row->dimension : Dimension::none;
        const auto fallback = default_range(dimension);
        range.low = fallback ? in_unit(fallback->first, unit) : -kNoLimit;
        range.high = fallback ? in_unit(fallback->second, unit) : kNoLimit;
    }
    property(variable, node_id(id + ".EURange"), browse("EURange"), "Range", range);
}

std::optional<std::pair<double, double>> UaDeviceBuilder::model_range(const PlannedItem& item) const {
    const DataObject& d = *item.object;
    // GB/T 39561.3 table A.x LValue/HValue (Minimum/Maximum): the item's own limits.
    std::optional<double> low, high;
    const auto number = [&](const char* key) -> std::optional<double> {
        const auto it = d.extra.find(key);
        if (it == d.extra.end() || !it->is_number()) return std::nullopt;
        const double v = it->get<double>();
        return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
    };
    low = number("minimum");
    high = number("maximum");
    // Else a LOWER_LIMIT/UPPER_LIMIT config (table 12) of the same component
    // whose units measure the same quantity (a limit without units, or in
    // another quantity, says nothing about this item).
    if (!low && !high && siblings_ != nullptr && item.unit != nullptr) {
        for (const auto& s : *siblings_) {
            if (&s == &item || !s.fixed_scalar() || !s.object->value->is_number() || s.unit == nullptr ||
                s.unit->dimension != item.unit->dimension)
                continue;
            const double common = s.object->value->get<double>() * s.unit->scale + s.unit->offset;
            const double own = in_unit(common, item.unit);
            if (s.type == "UPPER_LIMIT" && !high) high = own;
            if (s.type == "LOWER_LIMIT" && !low) low = own;
        }
    }
    if (!low && !high) return std::nullopt;
    const Dimension dimension = item.unit != nullptr ? item.unit->dimension : item.row->dimension;
    const auto fallback = default_range(dimension);
    const double lo = low ? *low : fallback ? in_unit(fallback->first, item.unit) : -kNoLimit;
    const double hi = high ? *high : fallback ? in_unit(fallback->second, item.unit) : kNoLimit;
    if (!(lo < hi)) return std::nullopt;  // contradictory limits: not used
    return std::make_pair(lo, hi);
}

std::string UaDeviceBuilder::unique_browse_name(std::size_t parent, const std::string& wanted, const std::string& fallback) {
    auto& taken = browse_names_[parent];
    std::string name = qualified(ns_, wanted);
    if (!taken.insert(name).second) {
        name = qualified(ns_, fallback);
        for (int n = 2; !taken.insert(name).second; ++n) name = qualified(ns_, fmt::format("{} ({})", fallback, n));
    }
    return name;
}

// ------------------------------------------------------------------ document

Result<UaDocument> plan_opcua(const Model& model, const MappingOptions& options) {
    auto plan = make_plan(model, options);
    if (!plan) return std::move(plan).error();
    UaDocument doc;
    doc.plan = std::move(*plan);
    doc.notes = doc.plan.notes;
    doc.unmapped = doc.plan.unmapped;
    auto& namespaces = OpcUaMappingBuilder::namespaces(doc.mapping);
    for (const auto& d : doc.plan.devices)
        namespaces.push_back(UaNamespace{"urn:nclink:device:" + d.dev_uuid, d.device->id, d.dev_uuid});
    doc.aliases = {{"Boolean", "i=1"},
                   {"Int32", "i=6"},
                   {"UInt32", "i=7"},
                   {"Double", "i=11"},
                   {"String", "i=12"},
                   {"NodeId", "i=17"},
                   {"LocalizedText", "i=21"},
                   {"BaseDataType", "i=24"},
                   {"Duration", "i=290"},
                   {"Range", "i=884"},
                   {"EUInformation", "i=887"},
                   {"Organizes", "i=35"},
                   {"HasModellingRule", "i=37"},
                   {"HasTypeDefinition", "i=40"},
                   {"HasSubtype", "i=45"},
                   {"HasProperty", "i=46"},
                   {"HasComponent", "i=47"}};
    if (options.opcua_profile == OpcUaProfile::cnc) {
        namespaces.push_back(UaNamespace{std::string(cnc_namespace_uri), "", ""});
        doc.cnc_namespace = static_cast<int>(namespaces.size());
        // OPC 40502 data types (CNC nodeset 1.0.0 NodeIds).
        for (const auto& [alias, id] : {std::pair<const char*, int>{"CncSpindleTurnDirection", 3001},
                                        {"CncChannelProgramStatus", 3002},
                                        {"CncChannelStatus", 3003},
                                        {"CncAxisStatus", 3004},
                                        {"CncSpindleStatus", 3005},
                                        {"CncOperationMode", 3006},
                                        {"CncPositionDataType", 3007}})
            doc.aliases.emplace_back(alias, numeric_node_id(doc.cnc_namespace, id));
    }
    for (std::size_t i = 0; i < doc.plan.devices.size(); ++i) {
        UaDeviceBuilder builder(doc, doc.plan.devices[i], static_cast<int>(i) + 1, doc.cnc_namespace);
        builder.build();
    }
    OpcUaMappingBuilder::index(doc.mapping);
    if (!doc.nodes.collision().empty())
        return make_error(ErrorCode::key_error, fmt::format("OPC UA NodeId \"{}\" is generated twice (an NC-Link id "
                                                            "equals a generated one)",
                                                            doc.nodes.collision()));
    return doc;
}

}  // namespace nclink::mapping_detail

namespace nclink {

std::string_view to_string(OpcUaProfile profile) noexcept { return profile == OpcUaProfile::cnc ? "cnc" : "basic"; }

std::optional<OpcUaProfile> opcua_profile_from_string(std::string_view text) noexcept {
    if (text == "basic") return OpcUaProfile::basic;
    if (text == "cnc") return OpcUaProfile::cnc;
    return std::nullopt;
}

std::string_view to_string(UaEncoding encoding) noexcept {
    switch (encoding) {
        case UaEncoding::scalar: return "scalar";
        case UaEncoding::json: return "json";
        case UaEncoding::enum_index: return "enum_index";
        case UaEncoding::two_state: return "two_state";
    }
    return "scalar";
}

const UaVariable* OpcUaMapping::find(std::string_view item_id) const {
    const auto it = by_item_.find(std::string(item_id));
    return it == by_item_.end() ? nullptr : &variables_[it->second];
}

Result<OpcUaMapping> opcua_mapping(const Model& model, const MappingOptions& options) {
    auto doc = mapping_detail::plan_opcua(model, options);
    if (!doc) return std::move(doc).error();
    return std::move(doc->mapping);
}

Result<MappedDocument> map_to_opcua(const Model& model, const MappingOptions& options) {
    auto doc = mapping_detail::plan_opcua(model, options);
    if (!doc) return std::move(doc).error();
    MappedDocument out;
    out.xml = mapping_detail::write_opcua(*doc, options);
    out.unmapped = std::move(doc->unmapped);
    out.notes = std::move(doc->notes);
    return out;
}

}  // namespace nclink
