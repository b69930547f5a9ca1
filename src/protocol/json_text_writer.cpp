#include "protocol/json_text_writer.hpp"
#include "protocol/decimal_text.hpp"

#include <charconv>
#include <cmath>

namespace nclink::protocol_detail {

nlohmann::detail::serializer<Json>& JsonTextWriter::serializer() {
    if (!serializer_) serializer_.emplace(nlohmann::detail::output_adapter<char>(out_), ' ', Json::error_handler_t::replace);
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
    } else if (magnitude < 1e-4 || magnitude >= 1e15) {
        // nlohmann's exponent form is printf's %e layout (d.ddde-05,
        // d.ddde+300), which to_chars writes with the shortest digits.
        end = std::to_chars(end, text + sizeof text, magnitude, std::chars_format::scientific).ptr;
    } else if (char* decimal = write_short_decimal(end, magnitude)) {
        // Short decimals, the bulk of machine values, skip the digit search.
        end = decimal;
    } else {
        // Fixed notation, shortest digits: nlohmann's layout for decimal
        // exponents -4..15, without going through the exponent form.
        end = std::to_chars(end, text + sizeof text, magnitude, std::chars_format::fixed).ptr;
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

void JsonTextWriter::result_fields(const ResponseStatus& status, const std::string& id, const std::optional<Json>& params,
                                   const std::optional<Json>& private_info) {
    code(status);
    raw(",\"id\":");
    string(id);
    if (params) {
        raw(",\"params\":");
        value(*params);
    }
    if (private_info) {
        raw(",\"privateInfo\":");
        value(*private_info);
    }
    reason(status);
}

void JsonTextWriter::response_head(const MessageId& msg_id, const std::optional<ResponseStatus>& status, const std::string& guid,
                                   const std::optional<Json>& private_info) {
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
