// plan_mtconnect: GB/T 39561.3 appendix A applied to a Plan. Device and
// component attributes per tables A.1 and A.3, components per table A.2 (with
// the Axes container it names and a Path for a controller's process data),
// data items per A.4 and the rows of mapping_table.cpp.
#include "mapping/mtconnect_plan.hpp"

#include "mapping/names.hpp"

#include <fmt/format.h>

#include <unordered_map>
#include <unordered_set>

namespace nclink::mapping_detail {
namespace {

/// A row's MTConnect type, with the unit deciding between linear and
/// angular quantities (a rotary axis' POSITION in rad is an ANGLE).
struct TypeChoice {
    std::string_view type;
    std::string_view sub_type;
    std::string_view element;
    Dimension dimension;
};

TypeChoice choose_type(const DataTypeRow& row, const UnitRow* unit) {
    TypeChoice c{row.mt_type, row.mt_sub_type, row.element, row.dimension};
    if (unit == nullptr || unit->dimension == row.dimension) return c;
    const Dimension u = unit->dimension;
    const std::string_view keep_sub = row.mt_sub_type == "ACTUAL" ? "ACTUAL" : "";
    if (row.dimension == Dimension::length && u == Dimension::angle) return {"ANGLE", keep_sub, "Angle", u};
    if (row.dimension == Dimension::velocity && u == Dimension::angular_velocity)
        return {"ANGULAR_VELOCITY", "", "AngularVelocity", u};
    if (row.dimension == Dimension::velocity && u == Dimension::rotational_speed)
        return {"ROTARY_VELOCITY", keep_sub, "RotaryVelocity", u};
    if (row.dimension == Dimension::acceleration && u == Dimension::angular_acceleration)
        return {"ANGULAR_ACCELERATION", "", "AngularAcceleration", u};
    return c;
}

class MtPlanner {
public:
    MtPlanner(MtPlan& out, const MappingOptions& options)
        : out_(out), prefix_(options.id_prefix.empty() ? "" : mtconnect_id(options.id_prefix) + ".") {}

    Result<void> run(const Plan& plan) {
        out_.notes = plan.notes;
        out_.unmapped = plan.unmapped;
        // Pass 1: every data object, and the ids taken from the model.
        for (const auto& device : plan.devices) {
            auto& devices = MtConnectMappingBuilder::devices(out_.mapping);
            MtDevice d;
            d.item_id = device.device->id;
            d.uuid = device.dev_uuid;
            d.id = id(device.device->id);
            d.name = nmtoken(device.device->name);
            if (d.name.empty()) d.name = nmtoken(device.device->id);
            if (d.name.empty()) d.name = "device";
            devices.push_back(d);
            if (auto r = take(d.id, device.device->id); !r) return r;
            device_uuid_ = device.dev_uuid;
            Owner owner;
            for (const auto& item : device.items)
                if (auto r = resolve(item, owner); !r) return r;
            for (const auto& c : device.components)
                if (auto r = resolve_component(c); !r) return r;
        }
        // Pass 2: the trees, with generated ids that avoid every model id.
        for (std::size_t i = 0; i < plan.devices.size(); ++i) {
            const auto& device = plan.devices[i];
            auto& d = MtConnectMappingBuilder::devices(out_.mapping)[i];
            d.availability_id = generate(d.id + "_avail");
            MtDeviceNode node;
            node.device = i;
            node.description = description(device.items, device.device->description);
            node.items = data_items(device.items);
            place(node.items, d.id, "Device", d.name);
            node.components = nodes(device.components, d.id, false);
            out_.devices.push_back(std::move(node));
        }
        return ok_result();
    }

private:
    /// Which Description attributes an owner has filled already.
    struct Owner {
        bool manufacturer = false;
        bool model = false;
        bool serial_number = false;
    };

    Result<void> resolve_component(const PlannedComponent& c) {
        if (auto r = take(id(c.component->id), c.component->id); !r) return r;
        if (!c.known_type)
            out_.unmapped.push_back(
                UnmappedItem{c.component->id, c.component->type, std::string(c.row->element), std::string(c.row->clause)});
        Owner owner;
        for (const auto& item : c.items)
            if (auto r = resolve(item, owner); !r) return r;
        for (const auto& child : c.children)
            if (auto r = resolve_component(child); !r) return r;
        return ok_result();
    }

    Result<void> resolve(const PlannedItem& item, Owner& owner) {
        const DataObject& d = *item.object;
        const DataTypeRow& row = *item.row;
        MtDataItem m;
        m.item_id = d.id;
        m.nclink_type = item.type;
        m.device_uuid = device_uuid_;

        // Tables A.1/A.3 rows 3-5: fixed manufacturer, model, serial number.
        if (item.fixed_scalar()) {
            const std::string value = scalar_text(*d.value);
            const auto attribute = [&](bool& done, const char* name) {
                if (done || value.empty()) return false;
                done = true;
                m.target = MtTarget::description_attribute;
                m.attribute = name;
                return true;
            };
            if ((item.type == "MANUFACTURER" && attribute(owner.manufacturer, "manufacturer")) ||
                (item.type == "MODEL" && attribute(owner.model, "model")) ||
                (item.type == "SERIAL_NUMBER" && attribute(owner.serial_number, "serialNumber"))) {
                return add(std::move(m), item);
            }
            // Table A.2 row 3: the axis kind chose the element.
            if (item.type == "CATAGORY" && item.placement.on_axis && (value == "linear" || value == "rotary")) {
                m.target = MtTarget::component_element;
                return add(std::move(m), item);
            }
        }

        m.id = id(d.id);
        m.name = nmtoken(d.name);
        std::string reason;
        if (!item.known_type || row.mt_fallback) {
            reason = item.known_type ? std::string(row.clause) : "not a chapter-7 type (GB/T 41970 tables 10, 12, 13)";
        } else if (d.kind != DataKind::single && row.value_form != MtValueForm::text && row.value_form != MtValueForm::condition) {
            reason = fmt::format("datatype {}: a {} value cannot carry a {}", to_string(d.kind), row.mt_type, to_string(d.kind));
        }
        if (!reason.empty()) {
            m.target = MtTarget::fallback;
            m.category = MtCategory::event;
            m.type = "MESSAGE";
            m.sub_type = extension_name(item.type);
            m.element = "Message";
            m.value_form = MtValueForm::text;
            out_.unmapped.push_back(UnmappedItem{d.id, d.type, "EVENT MESSAGE " + m.sub_type, std::move(reason)});
        } else {
            m.target = MtTarget::data_item;
            m.category = row.category;
            m.value_form = row.value_form;
            for (std::size_t i = 0; i < row.value_count; ++i)
                m.values.emplace_back(row.values[i].nclink, row.values[i].mtconnect);
            const TypeChoice choice = choose_type(row, item.unit);
            m.type = choice.type;
            m.sub_type = choice.sub_type;
            m.element = choice.element;
            if (row.value_form == MtValueForm::number) units(m, item, choice);
        }
        if (item.sample_interval_ms > 0) m.sample_rate = 1000.0 / item.sample_interval_ms;
        if (auto r = take(m.id, d.id); !r) return r;
        return add(std::move(m), item);
    }

    /// A.4 d) e): units in MTConnect's unit, nativeUnits the NC-Link one.
    void units(MtDataItem& m, const PlannedItem& item, const TypeChoice& choice) {
        const UnitRow* unit = item.unit;
        Dimension dimension = choice.dimension;
        if (unit != nullptr) {
            if (unit->dimension != choice.dimension) {
                dimension = unit->dimension;
                note(item.object->id, fmt::format("units \"{}\" do not measure what {} does: reported in {}", unit->spelling,
                                                  m.type, mtconnect_units(dimension)));
            }
            m.scale = unit->scale;
            m.offset = unit->offset;
            m.native_units = std::string(unit->native_units);
        }
        // MTConnect gives units to samples; numeric events (overrides) are
        // converted but carry none.
        if (m.category == MtCategory::sample) {
            m.units = std::string(mtconnect_units(dimension));
        } else {
            m.native_units.clear();
        }
    }

    Result<void> add(MtDataItem m, const PlannedItem& item) {
        index_[item.object] = MtConnectMappingBuilder::items(out_.mapping).size();
        MtConnectMappingBuilder::items(out_.mapping).push_back(std::move(m));
        out_.sources.push_back(&item);
        return ok_result();
    }

    /// The document id of a model id: escaped, after the prefix if one was asked for.
    std::string id(const std::string& nclink_id) const {
        return nclink_id.empty() ? std::string() : prefix_ + mtconnect_id(nclink_id);
    }

    /// Reserves an id taken from the model (xs:ID must be unique in the document).
    Result<void> take(const std::string& id, const std::string& nclink_id) {
        if (id.empty()) return ok_result();
        if (!used_.insert(id).second)
            return make_error(ErrorCode::key_error, fmt::format("MTConnect id \"{}\" of \"{}\" is used twice", id, nclink_id));
        return ok_result();
    }

    /// A generated id: `base`, or `base` with '_' appended until it is free.
    std::string generate(std::string base) {
        while (!used_.insert(base).second) base += '_';
        return base;
    }

    MtDescription description(const std::vector<PlannedItem>& items, const std::string& text) {
        MtDescription out;
        out.text = text;
        for (const auto& item : items) {
            const MtDataItem& m = mapped(item);
            if (m.target != MtTarget::description_attribute) continue;
            const std::string value = scalar_text(*item.object->value);
            if (m.attribute == "manufacturer") {
                out.manufacturer = nmtoken(value);
                if (out.manufacturer != value)
                    note(item.object->id, fmt::format("manufacturer \"{}\" written as the name "
                                                      "token \"{}\"",
                                                      value, out.manufacturer));
            } else if (m.attribute == "model") {
                out.model = value;
            } else {
                out.serial_number = value;
            }
        }
        return out;
    }

    std::vector<std::size_t> data_items(const std::vector<PlannedItem>& items) {
        std::vector<std::size_t> out;
        for (const auto& item : items) {
            const std::size_t i = index_.at(item.object);
            const MtTarget t = MtConnectMappingBuilder::items(out_.mapping)[i].target;
            if (t == MtTarget::data_item || t == MtTarget::fallback) out.push_back(i);
        }
        return out;
    }

    /// Components of one parent; AXIS components grouped in an Axes
    /// container (table A.2) unless the parent is an axis itself.
    std::vector<MtNode> nodes(const std::vector<PlannedComponent>& components, const std::string& parent_id, bool parent_is_axis) {
        std::vector<MtNode> out;
        std::size_t axes = SIZE_MAX;
        for (const auto& c : components) {
            MtNode node = component_node(c);
            if (!c.row->in_axes || parent_is_axis) {
                out.push_back(std::move(node));
                continue;
            }
            if (axes == SIZE_MAX) {
                axes = out.size();
                MtNode container;
                container.element = "Axes";
                container.id = generate(parent_id + "_axes");
                out.push_back(std::move(container));
            }
            out[axes].children.push_back(std::move(node));
        }
        return out;
    }

    MtNode component_node(const PlannedComponent& c) {
        MtNode node;
        node.element = c.type == "AXIS" ? (c.axis_kind == AxisKind::rotary ? "Rotary" : "Linear") : std::string(c.row->element);
        node.id = id(c.component->id);
        node.name = nmtoken(c.type == "AXIS" && !c.component->number.empty() ? c.component->number : c.component->name);
        node.description = description(c.items, c.component->description);
        std::vector<std::size_t> items = data_items(c.items);
        if (c.type == "CONTROLLER") {
            // A controller's process data goes to its Path (MTConnect Part 2);
            // conditions and the emergency stop stay on the Controller.
            MtNode path;
            path.element = "Path";
            path.name = "path";
            for (const std::size_t i : items) {
                const MtDataItem& m = MtConnectMappingBuilder::items(out_.mapping)[i];
                if (m.category == MtCategory::condition || m.type == "EMERGENCY_STOP") node.items.push_back(i);
                else path.items.push_back(i);
            }
            place(node.items, node.id, node.element, node.name);
            if (!path.items.empty()) {
                path.id = generate(node.id + "_path");
                place(path.items, path.id, path.element, path.name);
                node.children.push_back(std::move(path));
            }
        } else {
            node.items = std::move(items);
            place(node.items, node.id, node.element, node.name);
        }
        for (auto& child : nodes(c.children, node.id, c.type == "AXIS")) node.children.push_back(std::move(child));
        return node;
    }

    void place(const std::vector<std::size_t>& items, const std::string& id, const std::string& element, const std::string& name) {
        for (const std::size_t i : items) {
            MtDataItem& m = MtConnectMappingBuilder::items(out_.mapping)[i];
            m.component_id = id;
            m.component_element = element;
            m.component_name = name;
        }
    }

    const MtDataItem& mapped(const PlannedItem& item) const {
        return MtConnectMappingBuilder::items(out_.mapping)[index_.at(item.object)];
    }

    void note(const std::string& id, std::string message) { out_.notes.push_back(MappingNote{id, std::move(message)}); }

    MtPlan& out_;
    const std::string prefix_;
    std::string device_uuid_;
    std::unordered_set<std::string> used_;
    std::unordered_map<const DataObject*, std::size_t> index_;
};

}  // namespace

Result<MtPlan> plan_mtconnect(const Model& model, const MappingOptions& options) {
    auto plan = make_plan(model, options);
    if (!plan) return std::move(plan).error();
    MtPlan out;
    out.plan = std::move(*plan);
    MtPlanner planner(out, options);
    if (auto r = planner.run(out.plan); !r) return std::move(r).error();
    MtConnectMappingBuilder::index(out.mapping);
    return out;
}

}  // namespace nclink::mapping_detail
