// The hot-path Sample DTU encoder: writes JSON text straight into a buffer
// that only grows, so a steady upload loop never allocates.
#include <nclink/sample_encoder.hpp>

#include "protocol/decimal_text.hpp"

#include <charconv>
#include <cmath>
#include <cstring>

namespace nclink {
namespace {

/// Raw cursor over a std::string used as a growable byte buffer. The string
/// is kept at its full capacity (size == capacity we may write into) and the
/// cursor tracks the used length; this avoids std::string's per-append checks.
class Writer {
public:
    explicit Writer(std::string& buffer) : buffer_(buffer) {}

    /// Room for `n` more bytes; returns where to write them.
    char* reserve(std::size_t n) {
        if (buffer_.size() - used_ < n) grow(n);
        return buffer_.data() + used_;
    }
    void commit(char* end) { used_ = static_cast<std::size_t>(end - buffer_.data()); }
    void put(char c) {
        *reserve(1) = c;
        ++used_;
    }
    void put(std::string_view text) {
        char* p = reserve(text.size());
        if (!text.empty()) std::memcpy(p, text.data(), text.size());
        used_ += text.size();
    }
    std::string_view view() const { return {buffer_.data(), used_}; }
    void pop_if(char c) {
        if (used_ && buffer_[used_ - 1] == c) --used_;
    }

private:
    void grow(std::size_t n) {
        std::size_t size = buffer_.size() < 256 ? 256 : buffer_.size();
        while (size - used_ < n) size *= 2;
        buffer_.resize(size);
    }

    std::string& buffer_;
    std::size_t used_ = 0;
};

constexpr char kHex[] = "0123456789abcdef";

/// Length of a valid UTF-8 sequence starting at p (RFC 3629: no overlongs,
/// no surrogates, nothing above U+10FFFF), or 0 if invalid.
std::size_t utf8_sequence(const unsigned char* p, const unsigned char* end) noexcept {
    const unsigned char c = p[0];
    const std::size_t left = static_cast<std::size_t>(end - p);
    auto cont = [&](std::size_t i) { return i < left && (p[i] & 0xC0) == 0x80; };
    if (c >= 0xC2 && c <= 0xDF) return cont(1) ? 2 : 0;
    if (c >= 0xE0 && c <= 0xEF) {
        if (!cont(1) || !cont(2)) return 0;
        if (c == 0xE0 && p[1] < 0xA0) return 0;  // overlong
        if (c == 0xED && p[1] > 0x9F) return 0;  // surrogate
        return 3;
    }
    if (c >= 0xF0 && c <= 0xF4) {
        if (!cont(1) || !cont(2) || !cont(3)) return 0;
        if (c == 0xF0 && p[1] < 0x90) return 0;  // overlong
        if (c == 0xF4 && p[1] > 0x8F) return 0;  // above U+10FFFF
        return 4;
    }
    return 0;
}

void write_string(Writer& w, std::string_view text) {
    // Worst case: every byte becomes "\u00XX" (6) or U+FFFD (3 bytes).
    char* out = w.reserve(text.size() * 6 + 2);
    *out++ = '"';
    const auto* p = reinterpret_cast<const unsigned char*>(text.data());
    const auto* end = p + text.size();
    while (p < end) {
        const unsigned char c = *p;
        if (c >= 0x20 && c < 0x80 && c != '"' && c != '\\') {
            *out++ = static_cast<char>(c);
            ++p;
            continue;
        }
        if (c < 0x80) {
            *out++ = '\\';
            switch (c) {
                case '"': *out++ = '"'; break;
                case '\\': *out++ = '\\'; break;
                case '\b': *out++ = 'b'; break;
                case '\f': *out++ = 'f'; break;
                case '\n': *out++ = 'n'; break;
                case '\r': *out++ = 'r'; break;
                case '\t': *out++ = 't'; break;
                default:
                    *out++ = 'u';
                    *out++ = '0';
                    *out++ = '0';
                    *out++ = kHex[c >> 4];
                    *out++ = kHex[c & 0xF];
            }
            ++p;
            continue;
        }
        const std::size_t n = utf8_sequence(p, end);
        if (n == 0) {  // invalid byte: U+FFFD, as nlohmann's replace handler does
            *out++ = '\xEF';
            *out++ = '\xBF';
            *out++ = '\xBD';
            ++p;
            continue;
        }
        std::memcpy(out, p, n);
        out += n;
        p += n;
    }
    *out++ = '"';
    w.commit(out);
}

inline void write_int(Writer& w, std::int64_t value) {
    char* p = w.reserve(24);
    w.commit(std::to_chars(p, p + 24, value).ptr);
}

inline void write_uint(Writer& w, std::uint64_t value) {
    char* p = w.reserve(24);
    w.commit(std::to_chars(p, p + 24, value).ptr);
}

inline void write_double(Writer& w, double value) {
    if (!std::isfinite(value)) {
        w.put("null");
        return;
    }
    char* p = w.reserve(32);
    // Integral values below 2^53 print exactly as to_chars' shortest form
    // would ("414"), only faster.
    if (value > -9.0e15 && value < 9.0e15) {
        const auto integral = static_cast<std::int64_t>(value);
        if (static_cast<double>(integral) == value) {
            if (integral == 0 && std::signbit(value)) {
                std::memcpy(p, "-0.0", 4);  // keep the sign through a round trip
                w.commit(p + 4);
                return;
            }
            w.commit(std::to_chars(p, p + 32, integral).ptr);
            return;
        }
    }
    // Short decimals (decimal_text.hpp): several times cheaper than the
    // general shortest-digits search below.
    if (char* end = protocol_detail::write_short_decimal(p, value)) {
        w.commit(end);
        return;
    }
    w.commit(std::to_chars(p, p + 32, value).ptr);
}

inline void write_value(Writer& w, const SampleValue& v) {
    switch (v.kind()) {
        case SampleValue::Kind::float64: write_double(w, v.as_double()); return;
        case SampleValue::Kind::int64: write_int(w, v.as_int64()); return;
        case SampleValue::Kind::uint64: write_uint(w, v.as_uint64()); return;
        case SampleValue::Kind::boolean: w.put(v.as_bool() ? std::string_view("true") : std::string_view("false")); return;
        case SampleValue::Kind::null: w.put("null"); return;
        case SampleValue::Kind::text: write_string(w, v.as_text()); return;
        case SampleValue::Kind::json: {
            const auto text = v.as_text();
            w.put(text.empty() ? std::string_view("null") : text);
            return;
        }
    }
    w.put("null");
}

void write_header(Writer& w, const SampleDtuHeader& h) {
    w.put('{');
    if (h.msg_id) {
        w.put("\"@id\":");
        w.put(h.msg_id->dump(-1, ' ', false, Json::error_handler_t::replace));
        w.put(',');
    }
    w.put("\"guid\":");
    write_string(w, h.guid);
    w.put(",\"id\":");
    write_string(w, h.channel_id);
    w.put(",\"beginTime\":\"");
    write_int(w, h.begin_time_ms);
    w.put("\",\"data\":[");
}

void write_trailer(Writer& w, const SampleDtuHeader& h) {
    w.put(']');
    if (h.private_info) {
        w.put(",\"privateInfo\":");
        w.put(h.private_info->dump(-1, ' ', false, Json::error_handler_t::replace));
    }
    w.put('}');
}

/// One point's values: `size` of them, `stride` apart.
struct Strided {
    const SampleValue* values;
    std::size_t size;
    std::size_t stride;
};

template <class ColumnAt>
std::string_view encode_columns(std::string& buffer, const SampleDtuHeader& header, std::size_t count, ColumnAt column_at) {
    Writer w(buffer);
    write_header(w, header);
    for (std::size_t c = 0; c < count; ++c) {
        const Strided column = column_at(c);
        if (c) w.put(',');
        w.put("{\"data\":[");
        const SampleValue* value = column.values;
        for (std::size_t r = 0; r < column.size; ++r, value += column.stride) {
            write_value(w, *value);
            w.put(',');
        }
        w.pop_if(',');  // cheaper than a branch per value
        w.put("]}");
    }
    write_trailer(w, header);
    return w.view();
}

}  // namespace

SampleEncoder::SampleEncoder(std::size_t initial_capacity) { buffer_.resize(initial_capacity); }

std::string_view SampleEncoder::encode(const SampleDtuHeader& header, const SampleBlock& block) {
    return encode_columns(buffer_, header, block.points, [&](std::size_t p) {
        return Strided{block.values + p * block.rows, block.rows, 1};
    });
}

std::string_view SampleEncoder::encode(const SampleDtuHeader& header, const SampleRows& rows) {
    // A column of a row-major block is one value per row, a row apart: with
    // rows of thousands of points each read is in another page, which the
    // hardware prefetcher does not follow, so every cache line would be a
    // full miss (encoding 1.6x slower than from a column-major block at
    // 5,000 points x 100 rows). The lines a few columns ahead are requested
    // here instead: one prefetch per row per cache line (4 values).
    constexpr std::size_t kPerLine = 64 / sizeof(SampleValue);
    constexpr std::size_t kAhead = 2 * kPerLine;
    const bool prefetch = rows.points > kPerLine && rows.rows > 1;
    return encode_columns(buffer_, header, rows.points, [&](std::size_t p) {
        if (prefetch && p % kPerLine == 0 && p + kAhead < rows.points) {
            const SampleValue* ahead = rows.values + p + kAhead;
            for (std::size_t r = 0; r < rows.rows; ++r, ahead += rows.points) __builtin_prefetch(ahead);
        }
        return Strided{rows.values + p, rows.rows, rows.points};
    });
}

std::string_view SampleEncoder::encode(const SampleDtuHeader& header, const SampleColumn* columns, std::size_t count) {
    return encode_columns(buffer_, header, count, [&](std::size_t p) { return Strided{columns[p].values, columns[p].size, 1}; });
}

namespace {
template <class Write>
void append_with(std::string& out, Write write) {
    std::string scratch;
    Writer w(scratch);
    write(w);
    out.append(w.view());
}
}  // namespace

void append_json_string(std::string& out, std::string_view text) {
    append_with(out, [&](Writer& w) { write_string(w, text); });
}

void append_json_double(std::string& out, double value) {
    append_with(out, [&](Writer& w) { write_double(w, value); });
}

void append_sample_value(std::string& out, const SampleValue& value) {
    append_with(out, [&](Writer& w) { write_value(w, value); });
}

}  // namespace nclink
