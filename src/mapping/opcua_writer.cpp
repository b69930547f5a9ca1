// The NodeSet2 document (UANodeSet.xsd 1.05, values per Opc.Ua.Types.xsd) of
// a UaDocument.
#include "mapping/opcua_nodes.hpp"
#include "mapping/xml_writer.hpp"

#include <fmt/format.h>

namespace nclink::mapping_detail {
namespace {

constexpr std::string_view kUnitsNamespace = "http://www.opcfoundation.org/UA/units/un/cefact";

void localized_body(XmlWriter& w, std::string_view text) {
    w.element("uax:Locale", "en");
    w.element("uax:Text", text);
}

void write_value(XmlWriter& w, const UaValue& v) {
    using K = UaValue::Kind;
    if (v.kind == K::none) return;
    w.start("Value");
    switch (v.kind) {
        case K::none: break;
        case K::boolean: w.element("uax:Boolean", v.flag ? "true" : "false"); break;
        case K::int32: w.element("uax:Int32", std::to_string(v.integer)); break;
        case K::uint32: w.element("uax:UInt32", std::to_string(v.integer)); break;
        case K::number: w.element("uax:Double", number_text(v.number)); break;
        case K::string: w.element("uax:String", v.text); break;
        case K::localized:
            w.start("uax:LocalizedText");
            localized_body(w, v.text);
            w.end();
            break;
        case K::localized_list:
            w.start("uax:ListOfLocalizedText");
            for (const auto& text : v.list) {
                w.start("uax:LocalizedText");
                localized_body(w, text);
                w.end();
            }
            w.end();
            break;
        case K::eu_information:
            w.start("uax:ExtensionObject");
            w.start("uax:TypeId");
            w.element("uax:Identifier", "i=888");  // EUInformation, Default XML
            w.end();
            w.start("uax:Body");
            w.start("uax:EUInformation");
            w.element("uax:NamespaceUri", kUnitsNamespace);
            w.element("uax:UnitId", std::to_string(v.unit->unit_id));
            w.start("uax:DisplayName");
            localized_body(w, v.unit->display);
            w.end();
            w.start("uax:Description");
            localized_body(w, v.unit->description);
            w.end();
            w.end();
            w.end();
            w.end();
            break;
        case K::range:
            w.start("uax:ExtensionObject");
            w.start("uax:TypeId");
            w.element("uax:Identifier", "i=885");  // Range, Default XML
            w.end();
            w.start("uax:Body");
            w.start("uax:Range");
            w.element("uax:Low", number_text(v.low));
            w.element("uax:High", number_text(v.high));
            w.end();
            w.end();
            w.end();
            break;
        case K::node_id:
            w.start("uax:NodeId");
            w.element("uax:Identifier", v.text);
            w.end();
            break;
    }
    w.end();
}

void write_node(XmlWriter& w, const UaNode& n) {
    switch (n.node_class) {
        case UaNodeClass::object: w.start("UAObject"); break;
        case UaNodeClass::variable: w.start("UAVariable"); break;
        case UaNodeClass::object_type: w.start("UAObjectType"); break;
    }
    w.attr("NodeId", n.node_id);
    w.attr("BrowseName", n.browse_name);
    w.attr_if("ParentNodeId", n.parent);
    if (n.node_class == UaNodeClass::object_type && n.is_abstract) w.attr("IsAbstract", "true");
    if (n.node_class == UaNodeClass::variable) {
        w.attr_if("DataType", n.data_type);
        if (n.value_rank != -1) w.attr("ValueRank", std::to_string(n.value_rank));
        w.attr_if("ArrayDimensions", n.array_dimensions);
        if (n.access_level != 1) {
            w.attr("AccessLevel", std::to_string(n.access_level));
            w.attr("UserAccessLevel", std::to_string(n.access_level));
        }
        if (n.minimum_sampling_interval > 0) w.attr("MinimumSamplingInterval", number_text(n.minimum_sampling_interval));
    }
    w.element("DisplayName", n.display_name);
    if (!n.description.empty()) w.element("Description", n.description);
    w.start("References");
    for (const auto& r : n.references) {
        w.start("Reference");
        w.attr("ReferenceType", r.type);
        if (!r.forward) w.attr("IsForward", "false");
        w.text(r.target);
        w.end();
    }
    w.end();
    if (!n.extension.empty()) {
        w.start("Extensions");
        w.start("Extension");
        w.start("nclink:Item");
        w.attr("xmlns:nclink", "urn:nclink:mapping");
        for (const auto& [name, value] : n.extension) w.attr(name, value);
        w.end();
        w.end();
        w.end();
    }
    if (n.node_class == UaNodeClass::variable) write_value(w, n.value);
    w.end();
}

}  // namespace

std::string write_opcua(const UaDocument& doc, const MappingOptions& options) {
    const std::string time = creation_time(options);
    XmlWriter w;
    w.declaration();
    w.comment(doc.cnc_namespace != 0 ? "Written by nclink from an NC-Link model, GB/T 39561.3-2020 appendix B with "
                                       "OPC 40502 (CNC Systems); load the CNC nodeset first"
                                     : "Written by nclink from an NC-Link model, GB/T 39561.3-2020 appendix B");
    w.start("UANodeSet");
    w.attr("xmlns", "http://opcfoundation.org/UA/2011/03/UANodeSet.xsd");
    w.attr("xmlns:uax", "http://opcfoundation.org/UA/2008/02/Types.xsd");
    w.attr("xmlns:xsi", "http://www.w3.org/2001/XMLSchema-instance");
    w.attr("LastModified", time);

    w.start("NamespaceUris");
    for (const auto& ns : doc.mapping.namespaces()) w.element("Uri", ns.uri);
    w.end();

    w.start("Models");
    for (std::size_t i = 0; i < doc.plan.devices.size(); ++i) {
        const auto& device = *doc.plan.devices[i].device;
        w.start("Model");
        w.attr("ModelUri", doc.mapping.namespaces()[i].uri);
        w.attr("Version", device.version.empty() ? "1.0.0" : device.version);
        w.attr("PublicationDate", time);
        w.start("RequiredModel");
        w.attr("ModelUri", "http://opcfoundation.org/UA/");
        w.attr("Version", "1.04");
        w.attr("PublicationDate", "2019-05-01T00:00:00Z");
        w.end();
        if (doc.cnc_namespace != 0) {
            w.start("RequiredModel");
            w.attr("ModelUri", cnc_namespace_uri);
            w.attr("Version", "1.0.0");
            w.attr("PublicationDate", "2017-06-19T16:01:03Z");
            w.end();
        }
        w.end();
    }
    w.end();

    w.start("Aliases");
    for (const auto& [alias, id] : doc.aliases) {
        w.start("Alias");
        w.attr("Alias", alias);
        w.text(id);
        w.end();
    }
    w.end();

    for (const auto& n : doc.nodes.nodes()) write_node(w, n);
    return w.finish();
}

}  // namespace nclink::mapping_detail
