// A tiny XML builder: elements, attributes and text, escaped with
// xml_escape, indented two spaces. No parsing, no namespaces of its own.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace nclink::mapping_detail {

class XmlWriter {
public:
    /// Writes the XML declaration (UTF-8).
    void declaration();
    /// A comment line (text must not contain "--"; such runs become "- -").
    void comment(std::string_view text);
    /// Opens an element; attributes may follow until text or a child.
    void start(std::string_view name);
    /// An attribute of the element just started.
    void attr(std::string_view name, std::string_view value);
    /// The attribute only when value is not empty.
    void attr_if(std::string_view name, std::string_view value);
    /// Text content of the current element (escaped).
    void text(std::string_view text);
    /// Closes the current element (<x/> when it has no content).
    void end();
    /// start + text + end.
    void element(std::string_view name, std::string_view text);
    /// The document (closes what is still open).
    std::string finish();

private:
    struct Frame {
        std::string name;
        bool children = false;
        bool text = false;
    };
    void close_start_tag();
    void newline();

    std::string out_;
    std::vector<Frame> stack_;
    bool tag_open_ = false;
};

}  // namespace nclink::mapping_detail
