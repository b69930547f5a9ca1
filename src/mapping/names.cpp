// Identifier and name forms (see names.hpp) and the public id escaping of
// mapping.hpp: mtconnect_id / nclink_id_from_mtconnect.
#include "mapping/names.hpp"

#include <nclink/mapping.hpp>

#include <cstdint>

namespace nclink {
namespace {

bool ascii_alnum(unsigned char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); }

/// Bytes mtconnect_id keeps as they are inside an escaped id.
bool kept(unsigned char c) { return ascii_alnum(c) || c == '.' || c == '-'; }

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;  // lower case is never produced
}

}  // namespace

std::string mtconnect_id(std::string_view nclink_id) {
    if (mapping_detail::is_ascii_ncname(nclink_id) && nclink_id.front() != '_') return std::string(nclink_id);
    static constexpr char kHex[] = "0123456789ABCDEF";
    std::string out = "_";
    for (const char ch : nclink_id) {
        const auto c = static_cast<unsigned char>(ch);
        if (kept(c)) {
            out += ch;
        } else {
            out += '_';
            out += kHex[c >> 4];
            out += kHex[c & 0x0F];
        }
    }
    return out;
}

std::optional<std::string> nclink_id_from_mtconnect(std::string_view id) {
    if (id.empty()) return std::nullopt;
    if (id.front() != '_') {
        if (!mapping_detail::is_ascii_ncname(id)) return std::nullopt;
        return std::string(id);
    }
    std::string out;
    for (std::size_t i = 1; i < id.size(); ++i) {
        const auto c = static_cast<unsigned char>(id[i]);
        if (c != '_') {
            if (!kept(c)) return std::nullopt;
            out += id[i];
            continue;
        }
        if (i + 2 >= id.size()) return std::nullopt;
        const int hi = hex_value(id[i + 1]);
        const int lo = hex_value(id[i + 2]);
        if (hi < 0 || lo < 0) return std::nullopt;
        out += static_cast<char>(hi * 16 + lo);
        i += 2;
    }
    // Only the canonical form maps back ("_41" is never written for "A").
    if (mtconnect_id(out) != id) return std::nullopt;
    return out;
}

namespace mapping_detail {

bool is_ascii_ncname(std::string_view text) noexcept {
    if (text.empty()) return false;
    const auto first = static_cast<unsigned char>(text.front());
    if (!((first >= 'A' && first <= 'Z') || (first >= 'a' && first <= 'z') || first == '_')) return false;
    for (const char ch : text) {
        const auto c = static_cast<unsigned char>(ch);
        if (!(ascii_alnum(c) || c == '.' || c == '-' || c == '_')) return false;
    }
    return true;
}

std::string nmtoken(std::string_view name) {
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
    while (!name.empty() && space(name.front())) name.remove_prefix(1);
    while (!name.empty() && space(name.back())) name.remove_suffix(1);
    std::string out;
    std::size_t i = 0;
    while (i < name.size()) {
        const auto c = static_cast<unsigned char>(name[i]);
        if (c < 0x80) {
            out += (ascii_alnum(c) || c == '.' || c == '-' || c == '_' || c == ':') ? name[i] : '_';
            ++i;
            continue;
        }
        // Decode one UTF-8 sequence (the model is valid UTF-8; anything else is '_').
        std::size_t len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 1;
        std::uint32_t cp = len == 2 ? c & 0x1F : len == 3 ? c & 0x0F : c & 0x07;
        bool valid = len > 1 && i + len <= name.size();
        for (std::size_t k = 1; valid && k < len; ++k) {
            const auto b = static_cast<unsigned char>(name[i + k]);
            valid = (b & 0xC0) == 0x80;
            cp = (cp << 6) | (b & 0x3F);
        }
        if (!valid) len = 1;
        const bool letter = valid && ((cp >= 0xC0 && cp <= 0xFF && cp != 0xD7 && cp != 0xF7) || (cp >= 0x4E00 && cp <= 0x9FA5));
        if (letter) out.append(name.substr(i, len));
        else out += '_';
        i += len;
    }
    return out;
}

std::string extension_name(std::string_view type) {
    if (type.empty()) return "x:UNKNOWN";
    std::string out = "x:";
    for (const char ch : type) {
        const auto c = static_cast<unsigned char>(ch);
        if (c >= 'a' && c <= 'z') out += static_cast<char>(c - 'a' + 'A');
        else if ((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_') out += ch;
        else out += '_';
    }
    return out;
}

}  // namespace mapping_detail
}  // namespace nclink
