// Pieces shared by every DTU: the message id, the response status of
// table 18/19/20 and the decode/encode entry points.
#pragma once

#include <nclink/error.hpp>
#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace nclink {

/// "@id" (8.1.3). The standard says string; deployed clients send numbers too,
/// so any JSON scalar is kept and echoed verbatim. Absent = std::nullopt.
using MessageId = std::optional<Json>;

/// code/reason/error of a response (tables 18-20).
struct NCLINK_API ResponseStatus {
    bool ok = true;                     ///< "code": "OK" or "NG"
    std::optional<std::string> reason;  ///< "reason", table-19 string (or DEV_UNREACHABLE, or user text for codes < 0)
    std::optional<int> error;           ///< "error", table-19 number

    ResponseStatus() = default;
    /// NG with reason = reason(error.code) (exact table-19 string) and
    /// error = the numeric code; ErrorCode::success gives a plain OK.
    /// (error.message is for logs, never the wire.)
    explicit ResponseStatus(const Error& failure);

    static ResponseStatus success() { return {}; }
    static ResponseStatus failure(ErrorCode code) { return ResponseStatus(make_error(code)); }
    /// NG with any reason and number (user-defined codes < 0, DEV_UNREACHABLE).
    static ResponseStatus failure(std::string reason_text, std::optional<int> error_number);

    std::string_view code() const noexcept { return ok ? "OK" : "NG"; }
    /// The table-19 code of `error`, if it is one.
    std::optional<ErrorCode> error_code() const noexcept;
};

/// Decoding a DTU (errors as values, nothing ever thrown):
///   412 syntax error       - payload is not JSON, or not a JSON object
///   102 Parameter Missing  - a required key is absent
///   413 keys of arguments  - a required key is absent AND the object carries
///                            keys this DTU does not know (wrong DTU/keys)
///   405 Value type error   - a known key holds the wrong JSON type
/// Unknown keys next to all required ones are ignored (liberal).
/// Explicitly instantiated for every DTU type of dtu.hpp.
template <class T>
NCLINK_API Result<T> decode(std::string_view payload);
template <class T>
NCLINK_API Result<T> decode(const Json& dtu);
// Text arguments go to the payload overload (they also convert to Json).
template <class T>
Result<T> decode(const char* payload) {
    return decode<T>(std::string_view(payload));
}
template <class T>
Result<T> decode(const std::string& payload) {
    return decode<T>(std::string_view(payload));
}

/// Parses `payload` leniently to pick out "@id", so a request that fails to
/// decode can still be answered with its id. std::nullopt if there is none.
NCLINK_API MessageId peek_message_id(std::string_view payload);

/// Payloads nested deeper than this are refused with 412 before nlohmann
/// parses them (its serializer and comparisons recurse).
inline constexpr int max_payload_depth = 128;

}  // namespace nclink
