// The text of a Query response (8.2.12, table 33), written straight out.
// A Query of many items gets the largest answer on the request path: built
// as a tree of nlohmann objects (a std::map per entry) and then dumped, 100
// items cost ~80 us on the reference VM, three quarters of it building the
// tree, more than the broker's whole round trip. The text here is byte for
// byte what to_json(dtu).dump() gives (keys in the order nlohmann's std::map
// sorts them, strings escaped by nlohmann's own serializer with invalid UTF-8
// replaced), except that a double always gets its shortest digits (see
// number()), which the protocol tests check on generated answers.
#include "protocol/decimal_text.hpp"
#include "protocol/dtu_codec.hpp"

#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <string>

namespace nclink {
namespace {

class TextWriter {
public:
    explicit TextWriter(std::string& out)
        : out_(out), serializer_(nlohmann::detail::output_adapter<char>(out), ' ', Json::error_handler_t::replace) {}

    void raw(std::string_view text) { out_.append(text); }
    /// A value as nlohmann writes it, walked here so that its doubles go
    /// through number(); objects iterate in nlohmann's (sorted) key order.
    void value(const Json& value) {
        switch (value.type()) {
            case Json::value_t::number_float: number(value); return;
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
            default: serializer_.dump(value, false, false, 0); return;
        }
    }
    /// A double in nlohmann's notation (fixed for decimal exponents -4..15,
    /// ".0" on integral values, else its exponent form), with the shortest
    /// digits that read back to the same double. Short decimals, the bulk of
    /// machine values, are written without the digit search (decimal_text.hpp);
    /// nlohmann's own search, grisu2, is not always shortest there (about 1 in
    /// 2,500 such values, e.g. 460.47851 as 460.47851000000003): the only
    /// bytes in which this text differs from to_json(dtu).dump().
    void number(const Json& json) {
        const double value = json.get<double>();
        char text[32];
        char* end = nullptr;
        if (value > -1e15 && value < 1e15 && std::trunc(value) == value) {
            if (value == 0 && std::signbit(value)) {
                raw("-0.0");
                return;
            }
            end = std::to_chars(text, text + sizeof text, static_cast<std::int64_t>(value)).ptr;
            *end++ = '.';
            *end++ = '0';
        } else if (std::fabs(value) >= 1e-4) {
            end = detail::write_short_decimal(text, value);
        }
        if (end)
            out_.append(text, end);
        else
            serializer_.dump(json, false, false, 0);
    }
    /// A string as nlohmann writes it: printable ASCII needs no escaping and
    /// goes as is; anything else (quotes, control bytes, UTF-8 to validate)
    /// through the serializer.
    void string(const std::string& text) {
        for (const char c : text) {
            const auto byte = static_cast<unsigned char>(c);
            if (byte < 0x20 || byte >= 0x80 || c == '"' || c == '\\') {
                serializer_.dump(Json(text), false, false, 0);
                return;
            }
        }
        out_ += '"';
        out_.append(text);
        out_ += '"';
    }
    /// code, error, reason of a status, each behind the key that sorts
    /// before it: "code" opens the object, "error" and "reason" fall where
    /// the caller says.
    void code(const ResponseStatus& status) {
        raw("\"code\":\"");
        raw(status.code());
        raw("\"");
        if (status.error) {
            raw(",\"error\":");
            raw(std::to_string(*status.error));
        }
    }
    void reason(const ResponseStatus& status) {
        if (!status.reason) return;
        raw(",\"reason\":");
        string(*status.reason);
    }

private:
    std::string& out_;
    nlohmann::detail::serializer<Json> serializer_;
};

}  // namespace

template <>
std::string encode<QueryResponse>(const QueryResponse& dtu) {
    std::string out;
    out.reserve(64 + dtu.values.size() * 48);
    TextWriter w(out);
    // Top level, sorted: "@id" code error guid privateInfo reason values.
    w.raw("{");
    bool first = true;
    const auto comma = [&] {
        if (!first) w.raw(",");
        first = false;
    };
    if (dtu.msg_id) {
        comma();
        w.raw("\"@id\":");
        w.value(*dtu.msg_id);
    }
    if (dtu.status) {
        comma();
        w.code(*dtu.status);
    }
    if (!dtu.guid.empty()) {
        comma();
        w.raw("\"guid\":");
        w.string(dtu.guid);
    }
    if (dtu.private_info) {
        comma();
        w.raw("\"privateInfo\":");
        w.value(*dtu.private_info);
    }
    if (dtu.status) w.reason(*dtu.status);  // after "code": its comma is due
    comma();
    w.raw("\"values\":[");
    for (std::size_t i = 0; i < dtu.values.size(); ++i) {
        const QueryResult& result = dtu.values[i];
        // Entry, sorted: code error id params privateInfo reason values.
        w.raw(i == 0 ? "{" : ",{");
        w.code(result.status);
        w.raw(",\"id\":");
        w.string(result.id);
        if (result.params) {
            w.raw(",\"params\":");
            w.value(*result.params);
        }
        if (result.private_info) {
            w.raw(",\"privateInfo\":");
            w.value(*result.private_info);
        }
        w.reason(result.status);
        if (result.values) {
            w.raw(",\"values\":");
            w.value(*result.values);
        }
        w.raw("}");
    }
    w.raw("]}");
    return out;
}

}  // namespace nclink
