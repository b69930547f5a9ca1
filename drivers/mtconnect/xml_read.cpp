#include "mtconnect/xml_read.hpp"

#include <libxml/parser.h>
#include <libxml/xmlerror.h>

#include <limits>

namespace nclink::mtconnect {

Result<XmlDoc> parse_xml(std::string_view text, const std::string& what) {
    if (text.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        return make_error(ErrorCode::syntax_error, what + ": document too large");
    xmlParserCtxtPtr ctxt = xmlNewParserCtxt();
    if (!ctxt) return make_error(ErrorCode::unavailable, what + ": out of memory");
    XmlDoc doc(xmlCtxtReadMemory(ctxt, text.data(), static_cast<int>(text.size()), nullptr, nullptr,
                                 XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING | XML_PARSE_NOCDATA));
    std::string why;
    if (!doc || !ctxt->wellFormed) {
        // XML_PARSE_NOERROR keeps libxml2 off stderr; the context keeps the
        // last error for us (libxml2 2.9: the lastError member).
        const xmlError* e = &ctxt->lastError;
        why = e->message ? std::string(e->message) : std::string("not well-formed");
        while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
        if (e->line > 0) why = "line " + std::to_string(e->line) + ": " + why;
    }
    xmlFreeParserCtxt(ctxt);
    if (!why.empty() || !doc) return make_error(ErrorCode::syntax_error, what + " is not well-formed XML: " + why);
    if (!xmlDocGetRootElement(doc.get())) return make_error(ErrorCode::syntax_error, what + " has no root element");
    return doc;
}

std::string_view local_name(const xmlNode* node) noexcept {
    return node && node->name ? std::string_view(reinterpret_cast<const char*>(node->name)) : std::string_view();
}

std::string attribute(const xmlNode* node, const char* name) {
    xmlChar* v = xmlGetNoNsProp(const_cast<xmlNode*>(node), reinterpret_cast<const xmlChar*>(name));
    if (!v) return {};
    std::string out(reinterpret_cast<const char*>(v));
    xmlFree(v);
    return out;
}

bool has_attribute(const xmlNode* node, const char* name) {
    return xmlHasNsProp(const_cast<xmlNode*>(node), reinterpret_cast<const xmlChar*>(name), nullptr) != nullptr;
}

std::string text_of(const xmlNode* node) {
    xmlChar* v = xmlNodeGetContent(node);
    if (!v) return {};
    std::string out(reinterpret_cast<const char*>(v));
    xmlFree(v);
    return out;
}

std::vector<const xmlNode*> children(const xmlNode* node, std::string_view name) {
    std::vector<const xmlNode*> out;
    if (!node) return out;
    for (const xmlNode* c = node->children; c; c = c->next)
        if (c->type == XML_ELEMENT_NODE && (name.empty() || local_name(c) == name)) out.push_back(c);
    return out;
}

const xmlNode* child(const xmlNode* node, std::string_view name) {
    if (!node) return nullptr;
    for (const xmlNode* c = node->children; c; c = c->next)
        if (c->type == XML_ELEMENT_NODE && local_name(c) == name) return c;
    return nullptr;
}

std::string agent_errors_text(const xmlNode* root) {
    if (local_name(root) != "MTConnectError") return {};
    std::string out;
    auto add = [&](const xmlNode* e) {
        if (!out.empty()) out += "; ";
        out += attribute(e, "errorCode") + ": " + text_of(e);
    };
    for (const xmlNode* errors : children(root, "Errors"))
        for (const xmlNode* e : children(errors, "Error")) add(e);
    return out.empty() ? std::string("MTConnectError") : out;
}

}  // namespace nclink::mtconnect
