// Query parameters of the MTConnect REST requests (part 1 8.3: from, count,
// at, interval, heartbeat, path) and of GB/T 18759.6 tables 7-8, checked as
// an MTConnect agent checks them: a value that is no integer is
// INVALID_REQUEST, an integer outside what the buffer holds OUT_OF_RANGE
// (5.5.2: at before firstSequence or after lastSequence), at together with
// interval INVALID_REQUEST. Pure functions, no state.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace nclink::bridge {

/// MTConnectError errorCode values (MTConnectError_1.4.xsd ErrorCodeType).
enum class MtErrorCode {
    invalid_request,
    out_of_range,
    no_device,
    invalid_uri,
    invalid_path,  ///< a path= XPath that does not parse or selects nothing (1.4 schema: INVALID_PATH)
    unsupported,
    too_many,
    internal_error,
    asset_not_found,
    unauthorized,
};

/// "INVALID_REQUEST", ...
std::string_view to_string(MtErrorCode code) noexcept;
/// The HTTP status the bridge answers an error with (docs/bridge.md "Errors").
int http_status(MtErrorCode code) noexcept;

struct MtError {
    MtErrorCode code = MtErrorCode::invalid_request;
    std::string message;
};

/// The query parameters as parsed (first value of each name).
using QueryParams = std::multimap<std::string, std::string>;

struct SampleParams {
    std::optional<std::uint64_t> from;  ///< default: firstSequence
    std::size_t count = 100;
    std::optional<std::chrono::milliseconds> interval;  ///< streaming when set
    std::chrono::milliseconds heartbeat{10000};
    std::optional<std::string> path;
};

struct CurrentParams {
    std::optional<std::uint64_t> at;
    std::optional<std::uint64_t> count;  ///< GB/T 18759.6 table 7 Count: checked, then unused
    std::optional<std::chrono::milliseconds> interval;
    std::chrono::milliseconds heartbeat{10000};
    std::optional<std::string> path;
};

/// Parses /sample's parameters; checks count against `buffer_size`
/// (1..bufferSize). Names are case-sensitive as in part 1; GB/T 18759.6
/// spells them with a capital (From, Count, Interval, Path, At): both work.
/// Every value of a parameter given more than once is checked (a malformed
/// one is an error beside a good one), and differing values are
/// INVALID_REQUEST. A path with a NUL byte is INVALID_PATH (an XPath that
/// does not parse is found when it is evaluated).
std::optional<MtError> parse_sample_params(const QueryParams& query, std::size_t buffer_size, SampleParams& out);
/// /current's (and GB/T 18759.6 snapshot's) parameters: at, interval,
/// heartbeat, path, and table 7's Count (1..bufferSize).
std::optional<MtError> parse_current_params(const QueryParams& query, std::size_t buffer_size, CurrentParams& out);

/// from must lie in [firstSequence, nextSequence] (nextSequence: nothing yet, poll again).
std::optional<MtError> check_from(std::uint64_t from, std::uint64_t first, std::uint64_t next);
/// at must lie in [firstSequence, lastSequence].
std::optional<MtError> check_at(std::uint64_t at, std::uint64_t first, std::uint64_t last);

/// A non-negative decimal integer; nullopt for anything else ("", "+1", "1.0", "0x1", overflow).
std::optional<std::uint64_t> parse_unsigned(std::string_view text);

}  // namespace nclink::bridge
