// The text of a Query response (8.2.12, table 33), written straight out.
// A Query of many items gets the largest answer on the request path: built
// as a tree of nlohmann objects (a std::map per entry) and then dumped, 100
// items cost ~80 us on the reference VM, three quarters of it building the
// tree, more than the broker's whole round trip. The text here is byte for
// byte what to_json(dtu).dump() gives (keys in the order nlohmann's std::map
// sorts them, every value through nlohmann's own serializer with invalid
// UTF-8 replaced), which the protocol tests check on generated answers.
#include "protocol/dtu_codec.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace nclink {
namespace {

class TextWriter {
public:
    explicit TextWriter(std::string& out)
        : out_(out), serializer_(nlohmann::detail::output_adapter<char>(out), ' ', Json::error_handler_t::replace) {}

    void raw(std::string_view text) { out_.append(text); }
    void value(const Json& value) { serializer_.dump(value, false, false, 0); }
    /// A string as nlohmann writes it: printable ASCII needs no escaping and
    /// goes as is; anything else (quotes, control bytes, UTF-8 to validate)
    /// through the serializer.
    void string(const std::string& text) {
        for (const char c : text) {
            const auto byte = static_cast<unsigned char>(c);
            if (byte < 0x20 || byte >= 0x80 || c == '"' || c == '\\') {
                value(Json(text));
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
