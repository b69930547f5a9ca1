// The MTConnect 1.4 Devices document (MTConnectDevices_1.4.xsd) of an MtPlan,
// and the public entry points map_to_mtconnect / mtconnect_mapping.
#include "mapping/mtconnect_plan.hpp"
#include "mapping/xml_writer.hpp"

#include <fmt/format.h>

namespace nclink {
namespace mapping_detail {
namespace {

constexpr std::string_view kDevicesNs = "urn:mtconnect.org:MTConnectDevices:1.4";

void write_description(XmlWriter& w, const MtDescription& d) {
    if (d.empty()) return;
    w.start("Description");
    w.attr_if("manufacturer", d.manufacturer);
    w.attr_if("model", d.model);
    w.attr_if("serialNumber", d.serial_number);
    if (!d.text.empty()) w.text(d.text);
    w.end();
}

void write_data_item(XmlWriter& w, const MtDataItem& m, const PlannedItem* source) {
    w.start("DataItem");
    w.attr("category", to_string(m.category));
    w.attr("id", m.id);
    w.attr_if("name", m.name);
    w.attr("type", m.type);
    w.attr_if("subType", m.sub_type);
    w.attr_if("units", m.units);
    w.attr_if("nativeUnits", m.native_units);
    if (m.sample_rate) w.attr("sampleRate", number_text(*m.sample_rate));
    // A.4 c): a value fixed in the model is the constraint's only Value.
    if (source != nullptr && source->fixed_scalar()) {
        const auto observations = mtconnect_observations(m, *source->object->value);
        if (observations.size() == 1 && observations[0].exact && observations[0].value != "UNAVAILABLE" &&
            m.category != MtCategory::condition) {
            w.start("Constraints");
            w.element("Value", observations[0].value);
            w.end();
        }
    }
    w.end();
}

class Writer {
public:
    Writer(const MtPlan& plan, const std::vector<const PlannedItem*>& sources) : plan_(plan), sources_(sources) {}

    void items(XmlWriter& w, const std::vector<std::size_t>& indexes) {
        const auto& all = plan_.mapping.items();
        for (const std::size_t i : indexes) write_data_item(w, all[i], sources_[i]);
    }

    void node(XmlWriter& w, const MtNode& n) {
        w.start(n.element);
        w.attr("id", n.id);
        w.attr_if("name", n.name);
        write_description(w, n.description);
        if (!n.items.empty()) {
            w.start("DataItems");
            items(w, n.items);
            w.end();
        }
        if (!n.children.empty()) {
            w.start("Components");
            for (const auto& child : n.children) node(w, child);
            w.end();
        }
        w.end();
    }

private:
    const MtPlan& plan_;
    const std::vector<const PlannedItem*>& sources_;
};

}  // namespace

std::string write_mtconnect(const MtPlan& plan, const MappingOptions& options) {
    const std::vector<const PlannedItem*>& sources = plan.sources;
    XmlWriter w;
    w.declaration();
    w.comment("Written by nclink from an NC-Link model, GB/T 39561.3-2020 appendix A");
    w.start("MTConnectDevices");
    w.attr("xmlns", kDevicesNs);
    w.attr("xmlns:xsi", "http://www.w3.org/2001/XMLSchema-instance");
    w.attr("xsi:schemaLocation", std::string(kDevicesNs) + " http://schemas.mtconnect.org/schemas/MTConnectDevices_1.4.xsd");
    w.start("Header");
    w.attr("creationTime", creation_time(options));
    w.attr("sender", options.sender.empty() ? "nclink" : options.sender);
    w.attr("instanceId", std::to_string(options.instance_id == 0 ? 1 : options.instance_id));
    w.attr("version", "1.4.0");
    w.attr("bufferSize", "131072");
    w.attr("assetBufferSize", "1024");
    w.attr("assetCount", "0");
    w.end();
    w.start("Devices");
    Writer writer(plan, sources);
    for (const auto& node : plan.devices) {
        const MtDevice& d = plan.mapping.devices()[node.device];
        w.start("Device");
        w.attr("id", d.id);
        w.attr("name", d.name);
        w.attr("uuid", d.uuid);
        write_description(w, node.description);
        w.start("DataItems");
        w.start("DataItem");
        w.attr("category", "EVENT");
        w.attr("id", d.availability_id);
        w.attr("name", "avail");
        w.attr("type", "AVAILABILITY");
        w.end();
        writer.items(w, node.items);
        w.end();
        if (!node.components.empty()) {
            w.start("Components");
            for (const auto& c : node.components) writer.node(w, c);
            w.end();
        }
        w.end();
    }
    return w.finish();
}

}  // namespace mapping_detail

std::string_view to_string(MtCategory category) noexcept {
    switch (category) {
        case MtCategory::sample: return "SAMPLE";
        case MtCategory::event: return "EVENT";
        case MtCategory::condition: return "CONDITION";
    }
    return "EVENT";
}

const MtDataItem* MtConnectMapping::find(std::string_view item_id) const {
    const auto it = by_item_.find(std::string(item_id));
    return it == by_item_.end() ? nullptr : &items_[it->second];
}

const MtDataItem* MtConnectMapping::find_by_mtconnect_id(std::string_view id) const {
    const auto it = by_id_.find(std::string(id));
    return it == by_id_.end() ? nullptr : &items_[it->second];
}

const MtDevice* MtConnectMapping::device(std::string_view id_or_uuid) const {
    for (const auto& d : devices_)
        if (d.item_id == id_or_uuid || d.uuid == id_or_uuid) return &d;
    return nullptr;
}

Result<MtConnectMapping> mtconnect_mapping(const Model& model, const MappingOptions& options) {
    auto plan = mapping_detail::plan_mtconnect(model, options);
    if (!plan) return std::move(plan).error();
    return std::move(plan->mapping);
}

Result<MappedDocument> map_to_mtconnect(const Model& model, const MappingOptions& options) {
    auto plan = mapping_detail::plan_mtconnect(model, options);
    if (!plan) return std::move(plan).error();
    MappedDocument doc;
    doc.xml = mapping_detail::write_mtconnect(*plan, options);
    doc.unmapped = std::move(plan->unmapped);
    doc.notes = std::move(plan->notes);
    return doc;
}

}  // namespace nclink
