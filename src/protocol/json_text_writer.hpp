// Internal: JSON text written as nlohmann's dump() writes it (compact,
// object keys in its sorted order, strings escaped with invalid UTF-8
// replaced), but without building a tree first. Answers that are written
// straight out (a Query's, a Set's) use it for their parts.
//
// The plain cases, which are nearly all of a machine's values, take no
// detour: printable-ASCII strings, integers, booleans, null, and doubles
// (see number()). Anything else (a string to escape or validate) goes
// through nlohmann's own serializer, made on first use: making it costs a
// heap allocation, which an answer of plain values never pays.
#pragma once

#include <nclink/dtu_common.hpp>

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace nclink::protocol_detail {

class JsonTextWriter {
public:
    explicit JsonTextWriter(std::string& out) : out_(out) {}
    JsonTextWriter(const JsonTextWriter&) = delete;
    JsonTextWriter& operator=(const JsonTextWriter&) = delete;

    void raw(std::string_view text) { out_.append(text); }
    /// Any value, as dump() writes it.
    void value(const Json& value);
    /// The fields of one entry of a Query's "values" or a Set's "results",
    /// in sorted order, without braces: "code", "error", "id", "params",
    /// "privateInfo", "reason" (a Query entry's "values" sorts after them).
    void result_fields(const ResponseStatus& status, const std::string& id, const std::optional<Json>& params,
                       const std::optional<Json>& private_info);
    /// The opening brace and the keys of a response that sort before its
    /// list ("values", "results"): "@id", code, error, guid, privateInfo,
    /// reason, each that is set followed by a comma.
    void response_head(const MessageId& msg_id, const std::optional<ResponseStatus>& status, const std::string& guid,
                       const std::optional<Json>& private_info);

private:
    /// A double in nlohmann's notation (fixed for decimal exponents -4..15,
    /// ".0" on integral values, else its exponent form) with the shortest
    /// digits that read back to the same double, from libstdc++'s to_chars
    /// (Ryu; ~30 % cheaper than nlohmann's grisu2 here). grisu2 is not always
    /// shortest (about 1 short decimal in 2,500, e.g. 460.47851 as
    /// 460.47851000000003), nor the nearest of the shortest: the only bytes
    /// in which this writer's text differs from dump().
    void number(double value);
    /// A string as dump() writes it.
    void string(std::string_view text);
    /// "code":"OK|NG" and, when set, ,"error":N (a status's first keys in
    /// sorted order).
    void code(const ResponseStatus& status);
    /// ,"reason":"..." when the status has one (it sorts after "privateInfo").
    void reason(const ResponseStatus& status);
    nlohmann::detail::serializer<Json>& serializer();

    std::string& out_;
    std::optional<nlohmann::detail::serializer<Json>> serializer_;
};

}  // namespace nclink::protocol_detail
