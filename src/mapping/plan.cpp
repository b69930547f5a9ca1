// make_plan: selects the devices, reads every component and data object
// against the mapping tables once, for both the MTConnect and the OPC UA side.
#include "mapping/plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <unordered_map>

namespace nclink::mapping_detail {
namespace {

class Planner {
public:
    Planner(const Model& model, std::vector<MappingNote>& notes) : model_(model), notes_(notes) {
        for (const auto& channel : model.channels())
            for (const auto& id : channel.ids) {
                if (channel.sample_interval_ms <= 0) continue;
                auto [it, inserted] = interval_.emplace(id, channel.sample_interval_ms);
                if (!inserted) it->second = std::min(it->second, channel.sample_interval_ms);
            }
    }

    PlannedDevice device(const Device& device, std::string dev_uuid) {
        PlannedDevice out;
        out.device = &device;
        out.dev_uuid = std::move(dev_uuid);
        Placement placement;
        placement.on_device = true;
        out.items = items(device.children, placement);
        for (const auto& id : device.children.components)
            if (const Component* c = model_.component(id)) out.components.push_back(component(*c, false));
        return out;
    }

private:
    PlannedComponent component(const Component& c, bool below_axis) {
        PlannedComponent out;
        out.component = &c;
        out.type = normalize_component_type(c.type);
        if (out.type != c.type)
            note(c.id, fmt::format("component type \"{}\" read as {} (GB/T 41970 table 8)", c.type, out.type));
        out.row = find_component_row(out.type);
        out.known_type = out.row != nullptr;
        if (!out.known_type) out.row = &unknown_component_row();
        const bool axis = out.type == "AXIS";
        Placement placement;
        placement.on_controller = out.type == "CONTROLLER";
        placement.on_axis = axis;
        placement.in_axis = below_axis;
        out.items = items(c.children, placement);
        for (const auto& id : c.children.components)
            if (const Component* child = model_.component(id)) out.children.push_back(component(*child, below_axis || axis));
        if (axis) classify_axis(out);
        return out;
    }

    std::vector<PlannedItem> items(const Children& children, const Placement& placement) {
        std::vector<PlannedItem> out;
        for (const auto* list : {&children.data_items, &children.configs})
            for (const auto& id : *list)
                if (const DataObject* d = model_.data_object(id)) out.push_back(item(*d, placement));
        return out;
    }

    PlannedItem item(const DataObject& d, const Placement& placement) {
        PlannedItem out;
        out.object = &d;
        out.placement = placement;
        out.type = normalize_data_type(d.type);
        if (out.type != d.type)
            note(d.id, fmt::format("type \"{}\" read as {} (GB/T 41970 tables 10, 12, 13)", d.type, out.type));
        out.row = find_data_row(out.type, placement);
        out.known_type = out.row != nullptr;
        if (!out.known_type) out.row = &unknown_type_row();
        if (const auto it = interval_.find(d.id); it != interval_.end()) out.sample_interval_ms = it->second;
        if (!d.units.empty()) {
            out.unit = find_unit(d.units);
            out.units_unknown = out.unit == nullptr;
            if (out.units_unknown)
                note(d.id, fmt::format("units \"{}\" unknown: no unit conversion or "
                                       "EngineeringUnits",
                                       d.units));
        } else if (!out.row->default_units.empty()) {
            out.unit = find_unit(out.row->default_units);
        }
        return out;
    }

    /// Table A.2 rows 2-3: spindle or feed axis, linear or rotary.
    void classify_axis(PlannedComponent& axis) {
        const std::string& number = axis.component->number;
        const bool s_number = !number.empty() && (number[0] == 'S' || number[0] == 's') &&
                              std::all_of(number.begin() + 1, number.end(), [](char c) { return c >= '0' && c <= '9'; });
        axis.spindle = s_number || holds_spindle_item(axis);
        if (axis.spindle) {
            axis.axis_kind = AxisKind::rotary;
            return;
        }
        for (const auto& item : axis.items) {
            if (item.type != "CATAGORY" || !item.object->value || !item.object->value->is_string()) continue;
            const auto& word = item.object->value->get_ref<const std::string&>();
            if (word == "rotary") {
                axis.axis_kind = AxisKind::rotary;
                return;
            }
            if (word == "linear") {
                axis.axis_kind = AxisKind::linear;
                return;
            }
        }
        // Table 9: X, Y, Z linear; A, B, C rotary; U, V, W swivel; Jn joints.
        const char letter = number.empty() ? '\0' : static_cast<char>(std::toupper(static_cast<unsigned char>(number[0])));
        if (letter == 'X' || letter == 'Y' || letter == 'Z') {
            axis.axis_kind = AxisKind::linear;
        } else if (letter == 'A' || letter == 'B' || letter == 'C' || letter == 'U' || letter == 'V' || letter == 'W' ||
                   letter == 'J') {
            axis.axis_kind = AxisKind::rotary;
        } else {
            axis.axis_kind = AxisKind::linear;
            note(axis.component->id, fmt::format("axis kind unknown (number \"{}\", no CATAGORY linear/rotary): "
                                                 "taken as linear",
                                                 number));
        }
    }

    static bool holds_spindle_item(const PlannedComponent& c) {
        for (const auto& item : c.items)
            if (item.type == "SPINDLE_SPEED" || item.type == "SPINDLE_OVERRIDE" || item.type == "SPINDLE_MODE") return true;
        for (const auto& child : c.children)
            if (child.type != "AXIS" && holds_spindle_item(child)) return true;
        return false;
    }

    void note(const std::string& id, std::string message) { notes_.push_back(MappingNote{id, std::move(message)}); }

    const Model& model_;
    std::vector<MappingNote>& notes_;
    std::unordered_map<std::string, double> interval_;
};

}  // namespace

bool PlannedItem::fixed_scalar() const {
    return object->value && (object->value->is_string() || object->value->is_number() || object->value->is_boolean());
}

Result<Plan> make_plan(const Model& model, const MappingOptions& options) {
    std::vector<const Device*> selected;
    for (const auto& d : model.devices())
        if (options.device.empty() || d.id == options.device || resolve_dev_uuid(d) == options.device) selected.push_back(&d);
    if (model.devices().empty()) return make_error(ErrorCode::parameter_missing, "the model has no device");
    if (selected.empty())
        return make_error(ErrorCode::node_not_exists, fmt::format("no device \"{}\" in the model", options.device));
    if (!options.dev_uuid.empty() && selected.size() > 1)
        return make_error(ErrorCode::arguments_nimiety, "a terminal id override needs exactly one device (select one)");

    Plan plan;
    // Never dropped silently: what no device holds, and methods (MTConnect is
    // read-only, A.4; calling them is the OPC UA server's business, B.5 e).
    for (const auto& d : model.data_objects())
        if (d.device_id.empty())
            plan.unmapped.push_back(UnmappedItem{d.id, d.type, "not written",
                                                 "a data object of the root's configs belongs to "
                                                 "no device"});
    for (const auto& m : model.methods())
        plan.unmapped.push_back(UnmappedItem{m.id, "METHOD", "not written",
                                             "methods are no MTConnect DataItem (A.4: read-only) "
                                             "and no OPC UA variable (B.5 e) Method nodes are "
                                             "the OPC UA server's)"});
    Planner planner(model, plan.notes);
    for (const Device* d : selected) plan.devices.push_back(planner.device(*d, resolve_dev_uuid(*d, options.dev_uuid)));
    for (std::size_t i = 0; i < plan.devices.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (plan.devices[i].dev_uuid == plan.devices[j].dev_uuid)
                return make_error(ErrorCode::key_error,
                                  fmt::format("devices \"{}\" and \"{}\" share the terminal id "
                                              "\"{}\"",
                                              plan.devices[j].device->id, plan.devices[i].device->id, plan.devices[i].dev_uuid));
    return plan;
}

std::string number_text(double value) {
    std::string text = fmt::format("{}", value);
    for (char& c : text)
        if (c == 'e') c = 'E';
    return text;
}

std::string scalar_text(const Json& value) {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
    if (value.is_number_integer()) return value.dump();
    if (value.is_number()) {
        const double d = value.get<double>();
        return std::isfinite(d) ? number_text(d) : "";
    }
    return "";
}

std::string creation_time(const MappingOptions& options) {
    if (!options.creation_time.empty()) return options.creation_time;
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm utc{};
    gmtime_r(&now, &utc);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &utc);
    return stamp;
}

}  // namespace nclink::mapping_detail
