#include "core/json_locate.hpp"

#include <string>
#include <vector>

namespace nclink::core_detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::size_t skip_space(std::string_view text, std::size_t i) {
    while (i < text.size() && is_space(text[i])) ++i;
    return i;
}

void append_utf8(std::string& out, unsigned code) {
    if (code < 0x80) {
        out += static_cast<char>(code);
    } else if (code < 0x800) {
        out += static_cast<char>(0xC0 | (code >> 6));
        out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
        out += static_cast<char>(0xE0 | (code >> 12));
        out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
        out += static_cast<char>(0xF0 | (code >> 18));
        out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
        out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (code & 0x3F));
    }
}

std::optional<unsigned> hex4(std::string_view text, std::size_t i) {
    if (i + 4 > text.size()) return std::nullopt;
    unsigned value = 0;
    for (std::size_t k = i; k < i + 4; ++k) {
        const char c = text[k];
        value <<= 4;
        if (c >= '0' && c <= '9') value |= static_cast<unsigned>(c - '0');
        else if (c >= 'a' && c <= 'f') value |= static_cast<unsigned>(c - 'a' + 10);
        else if (c >= 'A' && c <= 'F') value |= static_cast<unsigned>(c - 'A' + 10);
        else return std::nullopt;
    }
    return value;
}

// Reads the string starting at text[i] == '"'; returns the index after its
// closing quote, or npos. `out` (when given) receives the decoded text.
std::size_t read_string(std::string_view text, std::size_t i, std::string* out) {
    ++i;
    while (i < text.size()) {
        const char c = text[i];
        if (c == '"') return i + 1;
        if (c != '\\') {
            if (out) *out += c;
            ++i;
            continue;
        }
        if (i + 1 >= text.size()) return std::string_view::npos;
        const char e = text[i + 1];
        i += 2;
        if (!out) {
            if (e == 'u') i += 4;
            continue;
        }
        switch (e) {
            case 'b': *out += '\b'; break;
            case 'f': *out += '\f'; break;
            case 'n': *out += '\n'; break;
            case 'r': *out += '\r'; break;
            case 't': *out += '\t'; break;
            case 'u': {
                auto code = hex4(text, i);
                if (!code) return std::string_view::npos;
                i += 4;
                if (*code >= 0xD800 && *code < 0xDC00 && i + 6 <= text.size() && text[i] == '\\' && text[i + 1] == 'u') {
                    if (auto low = hex4(text, i + 2); low && *low >= 0xDC00 && *low < 0xE000) {
                        *code = 0x10000 + ((*code - 0xD800) << 10) + (*low - 0xDC00);
                        i += 6;
                    }
                }
                append_utf8(*out, *code);
                break;
            }
            default: *out += e; break;  // \" \\ \/
        }
    }
    return std::string_view::npos;
}

// The index after the value starting at text[i]. Nested containers are
// skipped by counting brackets (no recursion: the depth is the text's).
std::size_t skip_value(std::string_view text, std::size_t i) {
    if (i >= text.size()) return std::string_view::npos;
    if (text[i] == '"') return read_string(text, i, nullptr);
    if (text[i] != '{' && text[i] != '[') {
        while (i < text.size() && !is_space(text[i]) && text[i] != ',' && text[i] != '}' && text[i] != ']') ++i;
        return i;
    }
    std::size_t depth = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (c == '"') {
            i = read_string(text, i, nullptr);
            if (i == std::string_view::npos) return i;
            continue;
        }
        if (c == '{' || c == '[') ++depth;
        if (c == '}' || c == ']') {
            if (--depth == 0) return i + 1;
        }
        ++i;
    }
    return std::string_view::npos;
}

std::optional<std::vector<std::string>> split_pointer(std::string_view pointer) {
    std::vector<std::string> tokens;
    if (pointer.empty()) return tokens;
    if (pointer.front() != '/') return std::nullopt;
    std::size_t start = 1;
    while (true) {
        const std::size_t end = pointer.find('/', start);
        const std::string_view raw = pointer.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
        std::string token;
        for (std::size_t k = 0; k < raw.size(); ++k) {
            if (raw[k] == '~' && k + 1 < raw.size() && (raw[k + 1] == '0' || raw[k + 1] == '1')) {
                token += raw[k + 1] == '0' ? '~' : '/';
                ++k;
            } else {
                token += raw[k];
            }
        }
        tokens.push_back(std::move(token));
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    return tokens;
}

}  // namespace

TextPosition position_of_offset(std::string_view text, std::size_t offset) {
    TextPosition p;
    if (offset > text.size()) offset = text.size();
    for (std::size_t i = 0; i < offset; ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c == '\n') {
            ++p.line;
            p.column = 1;
        } else if ((c & 0xC0) != 0x80) {  // continuation bytes belong to the previous character
            ++p.column;
        }
    }
    return p;
}

std::optional<TextPosition> locate_pointer(std::string_view text, std::string_view pointer) {
    const auto tokens = split_pointer(pointer);
    if (!tokens) return std::nullopt;
    std::size_t value = skip_space(text, 0);
    std::size_t found = value;  // what to report: the key of the last member walked into, or the value
    for (const std::string& token : *tokens) {
        if (value >= text.size()) return std::nullopt;
        if (text[value] == '{') {
            std::optional<std::size_t> key_at, value_at;
            std::size_t i = skip_space(text, value + 1);
            if (i < text.size() && text[i] == '}') return std::nullopt;
            while (i < text.size()) {
                if (text[i] != '"') return std::nullopt;
                std::string key;
                const std::size_t key_start = i;
                i = read_string(text, i, &key);
                if (i == std::string_view::npos) return std::nullopt;
                i = skip_space(text, i);
                if (i >= text.size() || text[i] != ':') return std::nullopt;
                i = skip_space(text, i + 1);
                if (key == token) key_at = key_start, value_at = i;  // the last duplicate wins
                i = skip_value(text, i);
                if (i == std::string_view::npos) return std::nullopt;
                i = skip_space(text, i);
                if (i < text.size() && text[i] == ',') {
                    i = skip_space(text, i + 1);
                    continue;
                }
                break;
            }
            if (!key_at) return std::nullopt;
            found = *key_at;
            value = *value_at;
        } else if (text[value] == '[') {
            if (token.empty() || token.size() > 9 || token.find_first_not_of("0123456789") != std::string::npos)
                return std::nullopt;
            const std::size_t index = std::stoul(token);
            std::size_t i = skip_space(text, value + 1);
            if (i < text.size() && text[i] == ']') return std::nullopt;
            for (std::size_t n = 0;; ++n) {
                if (n == index) break;
                i = skip_value(text, i);
                if (i == std::string_view::npos) return std::nullopt;
                i = skip_space(text, i);
                if (i >= text.size() || text[i] != ',') return std::nullopt;
                i = skip_space(text, i + 1);
            }
            found = value = i;
        } else {
            return std::nullopt;
        }
    }
    return position_of_offset(text, found);
}

}  // namespace nclink::core_detail
