#include "protocol/json_text_writer.hpp"
#include "protocol/decimal_text.hpp"

#include <charconv>
#include <cmath>
#include <cstring>

namespace nclink::protocol_detail {
namespace {

// nlohmann's layout of a decimal number (its to_chars: printf's %g with
// exponents -4..15 written out) for the digits d1..dk of a value
// 0.d1..dk x 10^n, as libstdc++'s shortest to_chars finds them (Ryu: ~25 %
// cheaper than grisu2 here, and always shortest).
char* lay_out(char* out, const char* digits, int k, int n) {
    if (k <= n && n <= 15) {  // digits[000].0
        std::memcpy(out, digits, static_cast<std::size_t>(k));
        std::memset(out + k, '0', static_cast<std::size_t>(n - k));
        out += n;
        *out++ = '.';
        *out++ = '0';
        return out;
    }
    if (0 < n && n <= 15) {  // dig.its
        std::memcpy(out, digits, static_cast<std::size_t>(n));
        out[n] = '.';
        std::memcpy(out + n + 1, digits + n, static_cast<std::size_t>(k - n));
        return out + k + 1;
    }
    if (-4 < n && n <= 0) {  // 0.[000]digits
        *out++ = '0';
        *out++ = '.';
        std::memset(out, '0', static_cast<std::size_t>(-n));
        out += -n;
        std::memcpy(out, digits, static_cast<std::size_t>(k));
        return out + k;
    }
    // d[.igits]e+XX, at least two exponent digits (printf's %g)
    *out++ = digits[0];
    if (k > 1) {
        *out++ = '.';
        std::memcpy(out, digits + 1, static_cast<std::size_t>(k - 1));
        out += k - 1;
    }
    *out++ = 'e';
    int e = n - 1;
    *out++ = e < 0 ? '-' : '+';
    if (e < 0) e = -e;
    if (e < 10) *out++ = '0';
    return std::to_chars(out, out + 4, e).ptr;
}

// The shortest digits of a finite, non-zero |value| and its decimal point
// position n (value = 0.digits x 10^n), in nlohmann's layout.
char* shortest(char* out, double value) {
    char sci[32];  // d[.ddd]e[+-]XXX
    const char* end = std::to_chars(sci, sci + sizeof sci, value, std::chars_format::scientific).ptr;
    char digits[24];
    int k = 0;
    const char* p = sci;
    for (; p < end && *p != 'e'; ++p)
        if (*p != '.') digits[k++] = *p;
    int exponent = 0;
    std::from_chars(p + 1 + (p[1] == '+'), end, exponent);
    return lay_out(out, digits, k, exponent + 1);
}

}  // namespace

nlohmann::detail::serializer<Json>& JsonTextWriter::serializer() {
    if (!serializer_)
        serializer_.emplace(nlohmann::detail::output_adapter<char>(out_), ' ', Json::error_handler_t::replace);
    return *serializer_;
}

void JsonTextWriter::value(const Json& value) {
    char text[24];
    switch (value.type()) {
        case Json::value_t::null: raw("null"); return;
        case Json::value_t::boolean: raw(value.get<bool>() ? "true" : "false"); return;
        case Json::value_t::number_integer:
            out_.append(text, std::to_chars(text, text + sizeof text, value.get<std::int64_t>()).ptr);
            return;
        case Json::value_t::number_unsigned:
            out_.append(text, std::to_chars(text, text + sizeof text, value.get<std::uint64_t>()).ptr);
            return;
        case Json::value_t::number_float: number(value.get<double>()); return;
        case Json::value_t::string: string(value.get_ref<const std::string&>()); return;
        case Json::value_t::array: {
            out_ += '[';
            bool first = true;
            for (const Json& element : value) {
                if (!first) out_ += ',';
                first = false;
                this->value(element);
            }
            out_ += ']';
            return;
        }
        case Json::value_t::object: {
            out_ += '{';
            bool first = true;
            for (auto it = value.begin(); it != value.end(); ++it) {
                if (!first) out_ += ',';
                first = false;
                string(it.key());
                out_ += ':';
                this->value(it.value());
            }
            out_ += '}';
            return;
        }
        default: serializer().dump(value, false, false, 0); return;  // binary, discarded
    }
}

void JsonTextWriter::number(double value) {
    char text[32];
    char* end = text;
    if (!std::isfinite(value)) {
        raw("null");  // as dump()
        return;
    }
    if (std::signbit(value)) *end++ = '-';
    const double magnitude = std::fabs(value);
    if (magnitude == 0) {
        *end++ = '0';
        *end++ = '.';
        *end++ = '0';
    } else if (magnitude < 1e15 && std::trunc(magnitude) == magnitude) {
        end = std::to_chars(end, end + 20, static_cast<std::int64_t>(magnitude)).ptr;
        *end++ = '.';
        *end++ = '0';
    } else if (char* decimal = magnitude >= 1e-4 ? nclink::detail::write_short_decimal(end, magnitude) : nullptr) {
        // Short decimals, the bulk of machine values, skip the digit search.
        end = decimal;
    } else {
        end = shortest(end, magnitude);
    }
    out_.append(text, end);
}

void JsonTextWriter::string(std::string_view text) {
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte < 0x20 || byte >= 0x80 || c == '"' || c == '\\') {
            serializer().dump(Json(std::string(text)), false, false, 0);
            return;
        }
    }
    out_ += '"';
    out_.append(text);
    out_ += '"';
}

void JsonTextWriter::code(const ResponseStatus& status) {
    raw("\"code\":\"");
    raw(status.code());
    raw("\"");
    if (status.error) {
        char text[16];
        raw(",\"error\":");
        out_.append(text, std::to_chars(text, text + sizeof text, *status.error).ptr);
    }
}

void JsonTextWriter::reason(const ResponseStatus& status) {
    if (!status.reason) return;
    raw(",\"reason\":");
    string(*status.reason);
}

void JsonTextWriter::response_head(const MessageId& msg_id, const std::optional<ResponseStatus>& status,
                                   const std::string& guid, const std::optional<Json>& private_info) {
    out_ += '{';
    if (msg_id) {
        raw("\"@id\":");
        value(*msg_id);
        out_ += ',';
    }
    if (status) {
        code(*status);
        out_ += ',';
    }
    if (!guid.empty()) {
        raw("\"guid\":");
        string(guid);
        out_ += ',';
    }
    if (private_info) {
        raw("\"privateInfo\":");
        value(*private_info);
        out_ += ',';
    }
    if (status && status->reason) {
        raw("\"reason\":");
        string(*status->reason);
        out_ += ',';
    }
}

}  // namespace nclink::protocol_detail
