#include "mtconnect/probe_document.hpp"

#include "mtconnect/xml_read.hpp"

#include <cstdlib>

namespace nclink::mtconnect {

namespace {

Result<ProbeItem> read_item(const xmlNode* node) {
    ProbeItem item;
    item.id = attribute(node, "id");
    item.name = attribute(node, "name");
    item.category = attribute(node, "category");
    item.type = attribute(node, "type");
    item.sub_type = attribute(node, "subType");
    item.units = attribute(node, "units");
    item.native_units = attribute(node, "nativeUnits");
    item.representation = attribute(node, "representation");
    if (const std::string rate = attribute(node, "sampleRate"); !rate.empty()) {
        char* end = nullptr;
        const double r = std::strtod(rate.c_str(), &end);
        if (end && *end == '\0' && r > 0 && r < 1e9) item.sample_rate = r;
    }
    if (item.id.empty() || item.category.empty() || item.type.empty())
        return make_error(ErrorCode::syntax_error, "probe: a DataItem (line " +
                                                       std::to_string(xmlGetLineNo(const_cast<xmlNode*>(node))) +
                                                       ") lacks id, category or type");
    if (const xmlNode* source = child(node, "Source")) item.source = text_of(source);
    if (const xmlNode* constraints = child(node, "Constraints"))
        for (const xmlNode* v : children(constraints, "Value")) item.constraint_values.push_back(text_of(v));
    return item;
}

Result<ProbeComponent> read_component(const xmlNode* node) {
    ProbeComponent c;
    c.element = std::string(local_name(node));
    c.id = attribute(node, "id");
    c.name = attribute(node, "name");
    c.uuid = attribute(node, "uuid");
    if (const xmlNode* d = child(node, "Description")) {
        c.description = text_of(d);
        for (const xmlAttr* a = d->properties; a; a = a->next)
            c.description_attributes[reinterpret_cast<const char*>(a->name)] = attribute(d, reinterpret_cast<const char*>(a->name));
    }
    for (const xmlNode* items : children(node, "DataItems"))
        for (const xmlNode* i : children(items, "DataItem")) {
            auto item = read_item(i);
            if (!item.ok()) return std::move(item).error();
            c.items.push_back(std::move(item).value());
        }
    for (const xmlNode* comps : children(node, "Components"))
        for (const xmlNode* sub : children(comps)) {
            auto read = read_component(sub);
            if (!read.ok()) return std::move(read).error();
            c.components.push_back(std::move(read).value());
        }
    return c;
}

}  // namespace

Result<ProbeDocument> read_probe(std::string_view xml) {
    auto parsed = parse_xml(xml, "probe");
    if (!parsed.ok()) return std::move(parsed).error();
    const xmlNode* root = xmlDocGetRootElement(parsed.value().get());
    if (const std::string errors = agent_errors_text(root); !errors.empty())
        return make_error(ErrorCode::unavailable, "probe: the agent answered an error: " + errors);
    if (local_name(root) != "MTConnectDevices")
        return make_error(ErrorCode::syntax_error,
                          "probe: expected an MTConnectDevices document, got <" + std::string(local_name(root)) + ">");
    ProbeDocument doc;
    const xmlNode* header = child(root, "Header");
    if (!header) return make_error(ErrorCode::syntax_error, "probe: MTConnectDevices without a Header");
    doc.instance_id = attribute(header, "instanceId");
    doc.version = attribute(header, "version");
    const xmlNode* devices = child(root, "Devices");
    if (!devices) return make_error(ErrorCode::syntax_error, "probe: MTConnectDevices without Devices");
    for (const xmlNode* d : children(devices)) {
        auto device = read_component(d);
        if (!device.ok()) return std::move(device).error();
        doc.devices.push_back(std::move(device).value());
    }
    if (doc.devices.empty()) return make_error(ErrorCode::syntax_error, "probe: the Devices element lists no device");
    return doc;
}

const ProbeComponent* find_device(const ProbeDocument& probe, std::string_view selector) {
    if (selector.empty()) return probe.devices.empty() ? nullptr : &probe.devices.front();
    for (const auto& d : probe.devices)
        if (d.uuid == selector) return &d;
    for (const auto& d : probe.devices)
        if (d.name == selector || d.id == selector) return &d;
    return nullptr;
}

}  // namespace nclink::mtconnect
