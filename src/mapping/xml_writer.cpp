// XmlWriter and xml_escape (XML 1.0, 5th edition, section 2.2 "Characters").
#include "mapping/xml_writer.hpp"

#include <nclink/mapping.hpp>

#include <cstdint>

namespace nclink {
namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

/// Length of the valid UTF-8 sequence at text[i] and its code point; 0 when
/// the bytes there are not valid UTF-8 (overlong, surrogate, > U+10FFFF, cut).
std::size_t decode(std::string_view text, std::size_t i, std::uint32_t& cp) {
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(text[i + k]); };
    const unsigned char c = b(0);
    std::size_t len = 0;
    std::uint32_t min = 0;
    if (c < 0x80) {
        cp = c;
        return 1;
    } else if ((c & 0xE0) == 0xC0) {
        len = 2, cp = c & 0x1F, min = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
        len = 3, cp = c & 0x0F, min = 0x800;
    } else if ((c & 0xF8) == 0xF0) {
        len = 4, cp = c & 0x07, min = 0x10000;
    } else {
        return 0;
    }
    if (i + len > text.size()) return 0;
    for (std::size_t k = 1; k < len; ++k) {
        if ((b(k) & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (b(k) & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    return len;
}

}  // namespace

std::string xml_escape(std::string_view text) {
    std::string out;
    out.reserve(text.size() + text.size() / 8);
    std::size_t i = 0;
    while (i < text.size()) {
        std::uint32_t cp = 0;
        const std::size_t len = decode(text, i, cp);
        if (len == 0) {
            out += kReplacement;
            ++i;
            continue;
        }
        switch (cp) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            // Kept as references so attribute-value normalization and
            // line-end handling cannot change them.
            case '\t': out += "&#9;"; break;
            case '\n': out += "&#10;"; break;
            case '\r': out += "&#13;"; break;
            default:
                if (cp < 0x20 || cp == 0xFFFE || cp == 0xFFFF)
                    out += kReplacement;  // not a Char of XML 1.0, not even as a reference
                else out.append(text.substr(i, len));
        }
        i += len;
    }
    return out;
}

namespace mapping_detail {

void XmlWriter::declaration() { out_ += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>"; }

void XmlWriter::comment(std::string_view text) {
    close_start_tag();
    if (!stack_.empty()) stack_.back().children = true;
    newline();
    std::string body = xml_escape(text);
    for (std::size_t p = body.find("--"); p != std::string::npos; p = body.find("--", p)) body.replace(p, 2, "- -");
    out_ += "<!-- " + body + " -->";
}

void XmlWriter::start(std::string_view name) {
    close_start_tag();
    if (!stack_.empty()) stack_.back().children = true;
    newline();
    out_ += '<';
    out_ += name;
    stack_.push_back(Frame{std::string(name)});
    tag_open_ = true;
}

void XmlWriter::attr(std::string_view name, std::string_view value) {
    out_ += ' ';
    out_ += name;
    out_ += "=\"";
    out_ += xml_escape(value);
    out_ += '"';
}

void XmlWriter::attr_if(std::string_view name, std::string_view value) {
    if (!value.empty()) attr(name, value);
}

void XmlWriter::text(std::string_view text) {
    close_start_tag();
    if (!stack_.empty()) stack_.back().text = true;
    out_ += xml_escape(text);
}

void XmlWriter::end() {
    const Frame frame = stack_.back();
    stack_.pop_back();
    if (tag_open_) {
        out_ += "/>";
        tag_open_ = false;
        return;
    }
    if (frame.children && !frame.text) newline();
    out_ += "</" + frame.name + ">";
}

void XmlWriter::element(std::string_view name, std::string_view text) {
    start(name);
    this->text(text);
    end();
}

std::string XmlWriter::finish() {
    while (!stack_.empty()) end();
    out_ += '\n';
    return std::move(out_);
}

void XmlWriter::close_start_tag() {
    if (tag_open_) {
        out_ += '>';
        tag_open_ = false;
    }
}

void XmlWriter::newline() {
    if (out_.empty()) return;
    out_ += '\n';
    out_.append(stack_.size() * 2, ' ');
}

}  // namespace mapping_detail
}  // namespace nclink
