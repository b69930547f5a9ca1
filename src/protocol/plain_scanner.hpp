// Internal: a direct scan of the plain JSON form nearly every application
// sends its requests in (printable ASCII strings without escapes, scalars,
// JSON whitespace between tokens). No lexer, no token buffers, no tree.
//
// It only ever says "this is exactly that" or "not plain": every caller
// falls back to the tree decoder on false, which reads everything JSON
// allows and gives the table-19 answer for what it refuses. So a scan may
// refuse more than it must (a number beyond 18 digits, an escape, a byte
// outside 0x20-0x7E), never accept what the tree would read differently.
#pragma once

#include <nclink/dtu_common.hpp>
#include <nclink/json.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace nclink::protocol_detail {

class PlainScanner {
public:
    explicit PlainScanner(std::string_view text) : p_(text.data()), end_(text.data() + text.size()) {}

    /// Skips whitespace; true (and steps over it) when the next byte is `c`.
    bool take(char c) {
        skip_space();
        if (p_ == end_ || *p_ != c) return false;
        ++p_;
        return true;
    }
    bool next_is(char c) {
        skip_space();
        return p_ != end_ && *p_ == c;
    }
    /// A string of printable ASCII without escapes, its text without the quotes.
    bool string(std::string_view& out) {
        if (!take('"')) return false;
        const char* const start = p_;
        for (; p_ != end_; ++p_) {
            const auto c = static_cast<unsigned char>(*p_);
            if (c == '"') {
                out = std::string_view(start, static_cast<std::size_t>(p_ - start));
                ++p_;
                return true;
            }
            if (c < 0x20 || c > 0x7E || c == '\\') return false;
        }
        return false;
    }
    /// A plain string, a number, true, false or null, as the Json value
    /// nlohmann's parser makes of it: an integer without a minus sign is
    /// number_unsigned, with one number_integer, anything with a fraction
    /// or an exponent number_float (correctly rounded, as strtod is).
    bool scalar(Json& out) {
        skip_space();
        if (p_ == end_) return false;
        if (*p_ == '"') {
            std::string_view text;
            if (!string(text)) return false;
            out = Json(std::string(text));
            return true;
        }
        if (literal("true")) return out = Json(true), true;
        if (literal("false")) return out = Json(false), true;
        if (literal("null")) return out = Json(nullptr), true;
        return number(out);
    }
    bool at_end() {
        skip_space();
        return p_ == end_;
    }

private:
    void skip_space() {
        while (p_ != end_ && (*p_ == ' ' || *p_ == '\n' || *p_ == '\r' || *p_ == '\t')) ++p_;
    }
    bool literal(std::string_view word) {
        if (static_cast<std::size_t>(end_ - p_) < word.size() || std::string_view(p_, word.size()) != word) return false;
        p_ += word.size();
        return true;
    }
    bool digit() const { return p_ != end_ && *p_ >= '0' && *p_ <= '9'; }
    std::size_t digits() {
        const char* const start = p_;
        while (digit()) ++p_;
        return static_cast<std::size_t>(p_ - start);
    }
    // RFC 8259's number: -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?
    bool number(Json& out) {
        const char* const start = p_;
        const bool negative = *p_ == '-';
        if (negative) ++p_;
        if (!digit()) return false;
        const std::size_t whole = *p_ == '0' ? (++p_, 1) : digits();
        bool integer = true;
        if (p_ != end_ && *p_ == '.') {
            ++p_;
            if (digits() == 0) return false;
            integer = false;
        }
        if (p_ != end_ && (*p_ == 'e' || *p_ == 'E')) {
            ++p_;
            if (p_ != end_ && (*p_ == '+' || *p_ == '-')) ++p_;
            if (digits() == 0) return false;
            integer = false;
        }
        if (integer) {
            // 18 digits fit both int64 and uint64; longer ones (where the
            // parser's overflow rules start) are left to it.
            if (whole > 18) return false;
            if (negative) {
                std::int64_t v = 0;
                std::from_chars(start, p_, v);
                out = Json(v);
            } else {
                std::uint64_t v = 0;
                std::from_chars(start, p_, v);
                out = Json(v);
            }
            return true;
        }
        double v = 0;
        const auto read = std::from_chars(start, p_, v);
        if (read.ec != std::errc() || read.ptr != p_ || !std::isfinite(v)) return false;  // 1e999, 1e-400: the parser decides
        out = Json(v);
        return true;
    }

    const char* p_;
    const char* const end_;
};

/// A plain list: `[` entries read by `entry(scan)`, separated by commas `]`.
template <typename ReadEntry>
bool plain_list(PlainScanner& scan, ReadEntry&& entry) {
    if (!scan.take('[')) return false;
    if (scan.take(']')) return true;
    do {
        if (!entry(scan)) return false;
    } while (scan.take(','));
    return scan.take(']');
}

/// The whole of a plain request, {"@id":"...","guid":"...","<list_key>":[...]}:
/// keys in any order, each once, "@id" (a string) and "guid" optional, the
/// list required and read by `list(scan)`; nothing after the object.
template <typename ReadList>
bool plain_request(std::string_view payload, std::string_view list_key, MessageId& msg_id, std::string& guid, ReadList&& list) {
    PlainScanner scan(payload);
    bool seen_at_id = false, seen_guid = false, seen_list = false;
    if (!scan.take('{') || scan.next_is('}')) return false;
    do {
        std::string_view key, text;
        if (!scan.string(key) || !scan.take(':')) return false;
        if (key == "@id" && !seen_at_id) {
            if (!scan.string(text)) return false;
            msg_id = Json(std::string(text));
            seen_at_id = true;
        } else if (key == "guid" && !seen_guid) {
            if (!scan.string(text)) return false;
            guid = std::string(text);
            seen_guid = true;
        } else if (key == list_key && !seen_list) {
            if (!list(scan)) return false;
            seen_list = true;
        } else {
            return false;
        }
    } while (scan.take(','));
    return scan.take('}') && scan.at_end() && seen_list;
}

}  // namespace nclink::protocol_detail
