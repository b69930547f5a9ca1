// The little the MTConnect readers need of libxml2: parse a document from
// memory without touching the network, and read elements by local name
// (MTConnect documents carry a versioned default namespace, 1.3, 1.4, 2.x:
// the readers match names, not namespaces, so any version is read).
#pragma once

#include <nclink/result.hpp>

#include <libxml/tree.h>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::mtconnect {

struct XmlDocFree {
    void operator()(xmlDoc* doc) const noexcept { xmlFreeDoc(doc); }
};
using XmlDoc = std::unique_ptr<xmlDoc, XmlDocFree>;

/// Parses `text`; a document that is not well-formed XML is a syntax_error
/// (412) naming `what`, the line and libxml2's reason. No DTD, no entity
/// expansion, no network (XML_PARSE_NONET).
Result<XmlDoc> parse_xml(std::string_view text, const std::string& what);

/// The element's local name ("DataItem" for <m:DataItem>).
std::string_view local_name(const xmlNode* node) noexcept;
/// The attribute's value, "" when absent.
std::string attribute(const xmlNode* node, const char* name);
/// True when the attribute is present.
bool has_attribute(const xmlNode* node, const char* name);
/// The element's text content (all descendant text), "" when none.
std::string text_of(const xmlNode* node);
/// The child elements, optionally only those of one local name.
std::vector<const xmlNode*> children(const xmlNode* node, std::string_view name = {});
/// The first child element of that local name, nullptr when none.
const xmlNode* child(const xmlNode* node, std::string_view name);
/// An MTConnectError document's errors ("OUT_OF_RANGE: from is ..."), "" when
/// `root` is not one (MTConnect 1.4 part 1, 8.4).
std::string agent_errors_text(const xmlNode* root);

}  // namespace nclink::mtconnect
