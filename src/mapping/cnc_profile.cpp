// OpcUaProfile::cnc: OPC 40502 (CNC Systems 1.0.0, namespace
// http://opcfoundation.org/UA/CNC) over the appendix-B document. Per device a
// CncInterface (below the device object) lists NC-Link AXIS components as
// CncAxisType or CncSpindleType and CONTROLLER components as CncChannelType.
// Every mandatory child of those types exists: an NC-Link data object whose
// type fills the slot becomes that child (its NodeId stays s=<NC-Link id>,
// its BrowseName is the slot's), the rest are placeholders without a value,
// or with one the model implies (IsRotational, ActChannel, Id, ...).
#include "mapping/opcua_builder.hpp"

#include <fmt/format.h>

#include <iterator>

namespace nclink::mapping_detail {
namespace {

using K = CncSlotKind;

// "derived" values of placeholders:
//   is_rotational  the axis kind (table A.2 row 3 / table 9)
//   false          IsInactive/IsVirtual: a modelled axis exists and is active
//   channel        ActChannel: NodeId of the device's first channel
//   channel_id     Id: 1-based index of the CONTROLLER in the device

// CncDriveType (OPC 40502 6.5.3), inherited by axes and spindles.
constexpr CncSlot kDrive[] = {
    {"ActChannel", K::data_item, "NodeId", -1, "", true, "", "channel"},
    {"ActLoad", K::analog, "Double", -1, "", true, "AXIS_LOAD", ""},
    {"ActPower", K::analog, "Double", -1, "", true, "POWER", ""},
    {"ActTorque", K::analog, "Double", -1, "", true, "TORQUE", ""},
    {"CmdTorque", K::analog, "Double", -1, "", true, "", ""},
    {"IsInactive", K::data_item, "Boolean", -1, "", true, "", "false"},
    {"IsVirtual", K::data_item, "Boolean", -1, "", true, "", "false"},
};

// CncAxisType (OPC 40502 6.5.4).
constexpr CncSlot kAxis[] = {
    {"ActStatus", K::data_item, "CncAxisStatus", -1, "", true, "", ""},
    {"IsReferenced", K::data_item, "Boolean", -1, "", true, "AXIS_TOREFPOINT", ""},
    {"IsRotational", K::data_item, "Boolean", -1, "", true, "", "is_rotational"},
    {"PosDirect", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosIndirect", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"ZeroOffset", K::analog, "Double", -1, "", true, "", ""},
};

// CncSpindleType (OPC 40502 6.5.5).
constexpr CncSlot kSpindle[] = {
    {"ActGear", K::data_item, "UInt32", -1, "", true, "", ""},
    {"ActOverride", K::analog_range, "Double", -1, "", true, "SPINDLE_OVERRIDE", ""},
    {"ActSpeed", K::analog, "Double", -1, "", true, "SPINDLE_SPEED ROTATION_SPEED", ""},
    {"ActStatus", K::data_item, "CncSpindleStatus", -1, "", true, "", ""},
    {"ActTurnDirection", K::data_item, "CncSpindleTurnDirection", -1, "", true, "", ""},
    {"AnglePos", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"CmdGear", K::data_item, "UInt32", -1, "", true, "", ""},
    {"CmdOverride", K::analog_range, "Double", -1, "", true, "", ""},
    {"CmdSpeed", K::analog, "Double", -1, "", true, "", ""},
};

// CncChannelType (OPC 40502 6.6.2).
constexpr CncSlot kChannel[] = {
    {"ActFeedrate", K::analog, "Double", -1, "", true, "FEED_SPEED", ""},
    {"ActGFunctions", K::data_item, "UInt32", 1, "", true, "", ""},
    {"ActJogIncrement", K::analog, "Double", -1, "", true, "", ""},
    {"ActMainProgramFile", K::data_item, "String", -1, "", true, "", ""},
    {"ActMainProgramFileOffset", K::data_item, "UInt32", -1, "", false, "", ""},
    {"ActMainProgramLine", K::data_item, "String", -1, "", false, "", ""},
    {"ActMainProgramName", K::data_item, "String", -1, "", true, "PROGRAM", ""},
    {"ActMFunctions", K::data_item, "UInt32", 1, "", true, "", ""},
    {"ActModalOffsetFunction", K::data_item, "UInt32", -1, "", true, "", ""},
    {"ActOperationMode", K::data_item, "CncOperationMode", -1, "", true, "", ""},
    {"ActOverride", K::analog, "Double", -1, "", true, "FEED_OVERRIDE", ""},
    {"ActProgramBlock", K::data_item, "String", 1, "3", true, "", ""},
    {"ActProgramFile", K::data_item, "String", -1, "", true, "", ""},
    {"ActProgramFileOffset", K::data_item, "UInt32", -1, "", false, "", ""},
    {"ActProgramLine", K::data_item, "String", -1, "", false, "LINE_NUMBER", ""},
    {"ActProgramName", K::data_item, "String", -1, "", true, "SUBPROGRAM", ""},
    {"ActProgramStatus", K::data_item, "CncChannelProgramStatus", -1, "", true, "", ""},
    {"ActStatus", K::data_item, "CncChannelStatus", -1, "", true, "", ""},
    {"BlockMode", K::data_item, "Boolean", -1, "", true, "SINGLE_BLOCK_MODE", ""},
    {"CmdFeedrate", K::analog, "Double", -1, "", true, "", ""},
    {"CmdOperationMode", K::data_item, "CncOperationMode", -1, "", true, "", ""},
    {"CmdOverride", K::analog, "Double", -1, "", true, "", ""},
    {"DryRunFeed", K::analog, "Double", -1, "", true, "", ""},
    {"FeedHold", K::data_item, "Boolean", -1, "", true, "FEED_HOLD", ""},
    {"Id", K::property, "UInt32", -1, "", true, "", "channel_id"},
    {"PosTcpBcsA", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpBcsB", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpBcsC", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpBcsX", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpBcsY", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpBcsZ", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpWcsA", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpWcsB", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpWcsC", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpWcsX", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpWcsY", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"PosTcpWcsZ", K::position, "CncPositionDataType", -1, "", true, "", ""},
    {"ToolId", K::data_item, "UInt32", -1, "", true, "TOOL_NUMBER", ""},
};

// CncPositionVariableType (OPC 40502 7.3.2) components. An axis' PosDirect
// takes its NC-Link POSITION and remaining distance; other position
// variables stay placeholders.
constexpr CncSlot kPosition[] = {
    {"ActPos", K::base, "Double", -1, "", true, "", ""},
    {"CmdPos", K::base, "Double", -1, "", true, "", ""},
    {"RemDist", K::base, "Double", -1, "", true, "", ""},
};
constexpr CncSlot kPosDirect[] = {
    {"ActPos", K::base, "Double", -1, "", true, "POSITION", ""},
    {"CmdPos", K::base, "Double", -1, "", true, "", ""},
    {"RemDist", K::base, "Double", -1, "", true, "PATH_LEFT_LENGTH RESIDUAL", ""},
};

/// OPC 40502 NodeIds (namespace-relative) of the types used.
int cnc_type_id(std::string_view name) {
    if (name == "CncChannelType") return 1002;
    if (name == "CncAxisType") return 1004;
    if (name == "CncSpindleType") return 1005;
    if (name == "CncInterfaceType") return 1007;
    if (name == "CncAxisListType") return 1008;
    if (name == "CncSpindleListType") return 1009;
    if (name == "CncChannelListType") return 1010;
    if (name == "CncPositionVariableType") return 2001;
    return 0;
}

bool listed(std::string_view list, std::string_view word) {
    while (!list.empty()) {
        const auto space = list.find(' ');
        if (list.substr(0, space) == word) return true;
        if (space == std::string_view::npos) break;
        list.remove_prefix(space + 1);
    }
    return false;
}

template <std::size_t N>
constexpr std::size_t size(const CncSlot (&)[N]) {
    return N;
}

}  // namespace

std::string UaDeviceBuilder::cnc_type(std::string_view name) const { return numeric_node_id(cnc_ns_, cnc_type_id(name)); }

CncRole UaDeviceBuilder::cnc_role(const PlannedComponent& c) const {
    if (c.type == "CONTROLLER") return CncRole::channel;
    if (c.type == "AXIS") return c.spindle ? CncRole::spindle : CncRole::axis;
    return CncRole::none;
}

std::size_t UaDeviceBuilder::cnc_list(CncRole role) const {
    switch (role) {
        case CncRole::axis: return axis_list_;
        case CncRole::spindle: return spindle_list_;
        case CncRole::channel: return channel_list_;
        case CncRole::none: break;
    }
    return components_folder_;
}

void UaDeviceBuilder::cnc_prepare() {
    // Channels first (axes point at the first one), then every slot's item.
    int channels = 0;
    const auto number = [&](const auto& self, const std::vector<PlannedComponent>& list) -> void {
        for (const auto& c : list) {
            if (c.type == "CONTROLLER") {
                channel_index_[c.component] = ++channels;
                if (first_channel_.empty()) first_channel_ = node_id(c.component->id);
            }
            self(self, c.children);
        }
    };
    number(number, device_.components);
    const auto match = [&](const auto& self, const std::vector<PlannedComponent>& list) -> void {
        for (const auto& c : list) {
            const CncRole role = cnc_role(c);
            if (role != CncRole::none) cnc_match(c, role, role == CncRole::channel ? channel_index_[c.component] : 0);
            self(self, c.children);
        }
    };
    match(match, device_.components);
}

void UaDeviceBuilder::cnc_match(const PlannedComponent& c, CncRole role, int channel) {
    // Device-level items count for the first channel: on a one-channel
    // machine (appendix B) that is where feed and program data sit.
    const bool device_items = role == CncRole::channel && channel == 1;
    const auto slots = [&](const CncSlot* table, std::size_t count, std::string_view type) {
        for (std::size_t i = 0; i < count; ++i) {
            const CncSlot& slot = table[i];
            const std::string path = fmt::format("{}/{}", type, slot.name);
            if (slot.kind == K::position && type == "CncAxisType" && slot.name == "PosDirect") {
                for (const auto& child : kPosDirect)
                    if (!child.matches.empty()) cnc_claim(c, child, fmt::format("{}/{}", path, child.name), false);
            } else if (!slot.matches.empty()) {
                cnc_claim(c, slot, path, device_items);
            }
        }
    };
    if (role == CncRole::axis) {
        slots(kDrive, size(kDrive), "CncAxisType");
        slots(kAxis, size(kAxis), "CncAxisType");
    } else if (role == CncRole::spindle) {
        slots(kDrive, size(kDrive), "CncSpindleType");
        slots(kSpindle, size(kSpindle), "CncSpindleType");
    } else {
        slots(kChannel, size(kChannel), "CncChannelType");
    }
}

void UaDeviceBuilder::cnc_claim(const PlannedComponent& c, const CncSlot& slot, const std::string& path, bool with_device_items) {
    const PlannedItem* item = cnc_candidate(c, slot.matches);
    if (item == nullptr && with_device_items) item = cnc_candidate(device_.items, slot.matches);
    if (item == nullptr) return;
    fills_[item->object] = CncFill{&slot, item, path, SIZE_MAX, cnc_ns_};
    slot_items_[{c.component, path}] = item->object;
}

const PlannedItem* UaDeviceBuilder::cnc_candidate(const std::vector<PlannedItem>& items, std::string_view matches) const {
    for (const auto& item : items)
        if (item.known_type && item.object->kind == DataKind::single && listed(matches, item.type) && fills_.count(item.object) == 0)
            return &item;
    return nullptr;
}

/// The component's own items, then those of components below it that are
/// not CNC objects themselves (an axis' SCREW or MOTOR).
const PlannedItem* UaDeviceBuilder::cnc_candidate(const PlannedComponent& c, std::string_view matches) const {
    if (const PlannedItem* item = cnc_candidate(c.items, matches)) return item;
    for (const auto& child : c.children)
        if (cnc_role(child) == CncRole::none)
            if (const PlannedItem* item = cnc_candidate(child, matches)) return item;
    return nullptr;
}

void UaDeviceBuilder::cnc_interface(std::size_t device_object) {
    const std::string base = device_.dev_uuid + ".CncInterface";
    UaNode n;
    n.node_id = node_id(base);
    n.browse_name = qualified(cnc_ns_, "CncInterface");
    n.display_name = "CncInterface";
    n.description = "OPC 40502 CNC interface of this NC-Link device";
    const std::size_t iface = doc_.nodes.add(std::move(n));
    doc_.nodes.link(device_object, iface, "HasComponent");
    doc_.nodes.reference(iface, "HasTypeDefinition", cnc_type("CncInterfaceType"), true);
    for (const auto& [name, out] : {std::pair<const char*, std::size_t*>{"CncAxisList", &axis_list_},
                                    {"CncChannelList", &channel_list_},
                                    {"CncSpindleList", &spindle_list_}}) {
        UaNode list;
        list.node_id = node_id(base + "." + name);
        list.browse_name = qualified(cnc_ns_, name);
        list.display_name = name;
        *out = doc_.nodes.add(std::move(list));
        doc_.nodes.link(iface, *out, "HasComponent");
        doc_.nodes.reference(*out, "HasTypeDefinition", cnc_type(std::string(name) + "Type"), true);
    }
    const auto text = [](std::string value) {
        UaValue v;
        v.kind = UaValue::Kind::string;
        v.text = std::move(value);
        return v;
    };
    property(iface, node_id(base + ".VendorName"), qualified(cnc_ns_, "VendorName"), "String",
             text(cnc_static_text("MANUFACTURER")));
    property(iface, node_id(base + ".VendorRevision"), qualified(cnc_ns_, "VendorRevision"), "String",
             text(cnc_static_text("VERSION")));
    property(iface, node_id(base + ".Version"), qualified(cnc_ns_, "Version"), "String", text("1.0.0"));
    const std::string model = cnc_static_text("MODEL");
    if (!model.empty()) property(iface, node_id(base + ".CncTypeName"), qualified(cnc_ns_, "CncTypeName"), "String", text(model));
}

/// A fixed value of the first CONTROLLER (else the device) with this type.
std::string UaDeviceBuilder::cnc_static_text(std::string_view type) const {
    const auto in = [&](const std::vector<PlannedItem>& items) -> std::string {
        for (const auto& item : items)
            if (item.type == type && item.fixed_scalar()) return scalar_text(*item.object->value);
        return "";
    };
    const auto search = [&](const auto& self, const std::vector<PlannedComponent>& list) -> std::string {
        for (const auto& c : list) {
            if (c.type == "CONTROLLER") {
                if (std::string text = in(c.items); !text.empty()) return text;
            }
            if (std::string text = self(self, c.children); !text.empty()) return text;
        }
        return "";
    };
    if (std::string text = search(search, device_.components); !text.empty()) return text;
    return in(device_.items);
}

void UaDeviceBuilder::cnc_structure(const PlannedComponent& c, CncRole role, std::size_t object) {
    if (role == CncRole::axis) {
        cnc_slots(c, kDrive, size(kDrive), "CncAxisType", object);
        cnc_slots(c, kAxis, size(kAxis), "CncAxisType", object);
    } else if (role == CncRole::spindle) {
        cnc_slots(c, kDrive, size(kDrive), "CncSpindleType", object);
        cnc_slots(c, kSpindle, size(kSpindle), "CncSpindleType", object);
    } else if (role == CncRole::channel) {
        cnc_slots(c, kChannel, size(kChannel), "CncChannelType", object);
    }
}

void UaDeviceBuilder::cnc_slots(const PlannedComponent& c, const CncSlot* slots, std::size_t count, std::string_view type_name,
                                std::size_t object) {
    for (std::size_t i = 0; i < count; ++i) {
        const CncSlot& slot = slots[i];
        if (slot.kind == K::position) {
            cnc_position(c, slot.name, type_name, object);
            continue;
        }
        const auto filled = slot_items_.find({c.component, fmt::format("{}/{}", type_name, slot.name)});
        if (filled != slot_items_.end()) {
            fills_[filled->second].parent = object;
        } else if (slot.mandatory) {
            cnc_placeholder(slot, object, fmt::format("{}.{}", c.component->id, slot.name), c);
        }
    }
}

std::size_t UaDeviceBuilder::cnc_position(const PlannedComponent& c, std::string_view name, std::string_view type_name,
                                          std::size_t object) {
    const std::string id = fmt::format("{}.{}", c.component->id, name);
    UaNode n;
    n.node_class = UaNodeClass::variable;
    n.node_id = node_id(id);
    n.browse_name = qualified(cnc_ns_, name);
    n.display_name = std::string(name);
    n.data_type = "CncPositionDataType";
    const std::size_t position = doc_.nodes.add(std::move(n));
    doc_.nodes.link(object, position, "HasComponent");
    doc_.nodes.reference(position, "HasTypeDefinition", cnc_type("CncPositionVariableType"), true);
    const bool direct = type_name == "CncAxisType" && name == "PosDirect";
    const UnitRow* unit = nullptr;
    for (const auto& child : direct ? kPosDirect : kPosition) {
        const auto filled = slot_items_.find({c.component, fmt::format("{}/{}/{}", type_name, name, child.name)});
        if (filled != slot_items_.end()) {
            fills_[filled->second].parent = position;
            if (child.name == "ActPos") unit = fills_[filled->second].item->unit;
        } else {
            cnc_placeholder(child, position, fmt::format("{}.{}", id, child.name), c);
        }
    }
    analog_properties(position, id, unit, nullptr, true, cnc_ns_);
    return position;
}

std::size_t UaDeviceBuilder::cnc_placeholder(const CncSlot& slot, std::size_t parent, const std::string& id,
                                             const PlannedComponent& c) {
    UaValue value;
    if (slot.derived == "is_rotational") {
        value.kind = UaValue::Kind::boolean;
        value.flag = c.axis_kind == AxisKind::rotary;
    } else if (slot.derived == "false") {
        value.kind = UaValue::Kind::boolean;
    } else if (slot.derived == "channel") {
        value.kind = UaValue::Kind::node_id;
        value.text = first_channel_.empty() ? "i=0" : first_channel_;
    } else if (slot.derived == "channel_id") {
        value.kind = UaValue::Kind::uint32;
        value.integer = channel_index_[c.component];
    }
    if (slot.kind == K::property)
        return property(parent, node_id(id), qualified(cnc_ns_, slot.name), std::string(slot.data_type), value);
    UaNode n;
    n.node_class = UaNodeClass::variable;
    n.node_id = node_id(id);
    n.browse_name = qualified(cnc_ns_, slot.name);
    n.display_name = std::string(slot.name);
    n.description = value.kind == UaValue::Kind::none ? "OPC 40502 placeholder: no NC-Link data object of the model supplies it"
                                                      : "OPC 40502 value derived from the NC-Link model";
    n.data_type = std::string(slot.data_type);
    n.value_rank = slot.value_rank;
    n.array_dimensions = std::string(slot.array_dimensions);
    n.value = std::move(value);
    const std::size_t index = doc_.nodes.add(std::move(n));
    doc_.nodes.link(parent, index, "HasComponent");
    const std::string_view type_definition = slot.kind == K::analog || slot.kind == K::analog_range ? ua::analog_item_type
                                             : slot.kind == K::base                                 ? ua::base_data_variable_type
                                                                                                    : ua::data_item_type;
    doc_.nodes.reference(index, "HasTypeDefinition", std::string(type_definition), true);
    if (slot.kind == K::analog || slot.kind == K::analog_range)
        analog_properties(index, id, nullptr, nullptr, slot.kind == K::analog, 0);
    return index;
}

}  // namespace nclink::mapping_detail
