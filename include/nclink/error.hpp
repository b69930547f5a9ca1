// Error codes of GB/T 41970-2022 table 19 and the error value used across nclink.
#pragma once

#include <nclink/export.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace nclink {

/// Error codes of table 19. The numeric value is what goes into the `error`
/// key of a response DTU; reason() gives the exact `reason` string.
enum class ErrorCode : int {
    success = 0,
    out_of_range = 101,
    parameter_missing = 102,
    unavailable = 202,
    timeout = 203,
    permission_denied = 301,
    node_not_exists = 401,
    no_index = 402,
    no_key = 403,
    memory_configured = 404,
    value_type = 405,
    unsupported_get_length = 406,
    unsupported_get_attributes = 407,
    unsupported_get_keys = 408,
    arguments_nimiety = 409,
    key_error = 410,
    attribute_error = 411,
    syntax_error = 412,
    keys_of_arguments = 413,
    unsupported_terminal_id = 414,
    insufficient_dynamic_sampling = 415,
    insufficient_event = 416,
    insufficient_method = 417,
    method_action_type = 418,
    filter_type = 419,
    trigger_type = 420,
    filter_arguments_mismatch = 421,
};

/// The exact `reason` string of table 19 ("Node not exists", "Out of Range", ...).
/// Thread-safe (returns static storage).
NCLINK_API std::string_view reason(ErrorCode code) noexcept;

/// Numeric code as sent in the `error` key.
constexpr int to_int(ErrorCode code) noexcept { return static_cast<int>(code); }

/// Maps a numeric code back; std::nullopt for codes table 19 does not define.
/// (Negative, user-defined codes are not ErrorCode values.)
NCLINK_API std::optional<ErrorCode> error_code_from_int(int value) noexcept;

/// Maps a table-19 reason string back to its code (exact match first, then
/// case- and space-insensitive, because deployed peers vary the spelling).
NCLINK_API std::optional<ErrorCode> error_code_from_reason(std::string_view reason) noexcept;

/// The reason agents send for connection-error scenarios 8.3.4/8.3.5
/// (tables 53 and 54). It is not in table 19; it travels with error 301.
inline constexpr std::string_view dev_unreachable_reason = "DEV_UNREACHABLE";

/// An error as a value: the table-19 code to answer with and a human-readable
/// detail for logs and diagnostics (never put on the wire as `reason`).
struct NCLINK_API Error {
    ErrorCode code = ErrorCode::syntax_error;
    std::string message;
    /// Where in the input the error is, as a JSON pointer (RFC 6901), e.g.
    /// "/broker/uri" for a configuration key; empty when not known. Readers
    /// of JSON input fill it so a tool can show the line and column.
    std::string pointer;

    /// "401 Node not exists: <message>" for logs.
    std::string describe() const;
};

inline Error make_error(ErrorCode code, std::string message = {}) {
    Error error;
    error.code = code;
    error.message = std::move(message);
    return error;
}

/// A vendor's own error: table 19 leaves the codes below 0 and their reasons
/// to the user. `code` < 0 goes on the wire unchanged with `reason` as its
/// `reason`; any other code table 19 does not define is answered 202
/// Unavailable, its number kept in the text (docs/wire.md, "Vendor errors").
inline Error vendor_error(int code, std::string reason) { return make_error(static_cast<ErrorCode>(code), std::move(reason)); }

}  // namespace nclink
