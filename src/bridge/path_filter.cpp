#include "bridge/path_filter.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <libxml/xmlerror.h>
#include <libxml/xpath.h>

#include <memory>
#include <mutex>

namespace nclink::bridge {
namespace {

void ignore_error(void*, const char*, ...) {}
void ignore_structured(void*, xmlErrorPtr) {}

bool is_element(const xmlNode* node, const char* name) {
    return node->type == XML_ELEMENT_NODE && xmlStrcmp(node->name, reinterpret_cast<const xmlChar*>(name)) == 0;
}

void add_id(const xmlNode* node, std::set<std::string>& ids) {
    xmlChar* id = xmlGetProp(node, reinterpret_cast<const xmlChar*>("id"));
    if (id) {
        ids.insert(reinterpret_cast<const char*>(id));
        xmlFree(id);
    }
}

void collect(const xmlNode* node, std::set<std::string>& ids) {
    if (is_element(node, "DataItem")) {
        add_id(node, ids);
        return;
    }
    for (const xmlNode* child = node->children; child; child = child->next)
        if (child->type == XML_ELEMENT_NODE) collect(child, ids);
}

}  // namespace

std::optional<MtError> select_data_items(const std::string& devices_xml, const std::string& xpath, std::set<std::string>& ids) {
    static std::once_flag init;
    std::call_once(init, [] { xmlInitParser(); });
    // libxml2 keeps its error handlers per thread: silence them for this one.
    xmlSetGenericErrorFunc(nullptr, ignore_error);
    xmlSetStructuredErrorFunc(nullptr, ignore_structured);

    // Element names in path= carry no prefix: read the document without its
    // default namespace so //DataItem matches.
    std::string text = devices_xml;
    const std::string ns = " xmlns=\"urn:mtconnect.org:MTConnectDevices:1.4\"";
    if (auto at = text.find(ns); at != std::string::npos) text.erase(at, ns.size());

    std::unique_ptr<xmlDoc, void (*)(xmlDocPtr)> doc(
        xmlReadMemory(text.data(), static_cast<int>(text.size()), "devices.xml", "UTF-8", XML_PARSE_NONET), xmlFreeDoc);
    if (!doc) return MtError{MtErrorCode::internal_error, "the Devices document does not parse"};
    std::unique_ptr<xmlXPathContext, void (*)(xmlXPathContextPtr)> context(xmlXPathNewContext(doc.get()), xmlXPathFreeContext);
    if (!context) return MtError{MtErrorCode::internal_error, "no XPath context"};
    std::unique_ptr<xmlXPathObject, void (*)(xmlXPathObjectPtr)> result(
        xmlXPathEvalExpression(reinterpret_cast<const xmlChar*>(xpath.c_str()), context.get()), xmlXPathFreeObject);
    if (!result) return MtError{MtErrorCode::invalid_path, "the path '" + xpath.substr(0, 200) + "' is no valid XPath"};
    if (result->type != XPATH_NODESET || !result->nodesetval || result->nodesetval->nodeNr == 0)
        return MtError{MtErrorCode::invalid_path, "the path '" + xpath.substr(0, 200) + "' selects no data item"};
    const std::size_t before = ids.size();
    bool any_element = false;
    for (int i = 0; i < result->nodesetval->nodeNr; ++i) {
        const xmlNode* node = result->nodesetval->nodeTab[i];
        if (!node || node->type != XML_ELEMENT_NODE) continue;
        any_element = true;
        collect(node, ids);
    }
    if (!any_element) return MtError{MtErrorCode::invalid_path, "the path '" + xpath.substr(0, 200) + "' selects no element"};
    (void)before;
    return std::nullopt;
}

}  // namespace nclink::bridge
