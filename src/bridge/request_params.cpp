#include "bridge/request_params.hpp"

#include <limits>
#include <vector>

namespace nclink::bridge {

std::string_view to_string(MtErrorCode code) noexcept {
    switch (code) {
        case MtErrorCode::invalid_request: return "INVALID_REQUEST";
        case MtErrorCode::out_of_range: return "OUT_OF_RANGE";
        case MtErrorCode::no_device: return "NO_DEVICE";
        case MtErrorCode::invalid_uri: return "INVALID_URI";
        case MtErrorCode::invalid_path: return "INVALID_PATH";
        case MtErrorCode::unsupported: return "UNSUPPORTED";
        case MtErrorCode::too_many: return "TOO_MANY";
        case MtErrorCode::internal_error: return "INTERNAL_ERROR";
        case MtErrorCode::asset_not_found: return "ASSET_NOT_FOUND";
        case MtErrorCode::unauthorized: return "UNAUTHORIZED";
    }
    return "INTERNAL_ERROR";
}

int http_status(MtErrorCode code) noexcept {
    switch (code) {
        case MtErrorCode::invalid_request:
        case MtErrorCode::out_of_range:
        case MtErrorCode::invalid_path: return 400;
        case MtErrorCode::no_device:
        case MtErrorCode::invalid_uri:
        case MtErrorCode::asset_not_found: return 404;
        case MtErrorCode::unsupported: return 400;
        case MtErrorCode::too_many: return 503;
        case MtErrorCode::unauthorized: return 401;
        case MtErrorCode::internal_error: return 500;
    }
    return 500;
}

std::optional<std::uint64_t> parse_unsigned(std::string_view text) {
    if (text.empty() || text.size() > 20) return std::nullopt;
    std::uint64_t value = 0;
    for (char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
        const std::uint64_t digit = static_cast<std::uint64_t>(c - '0');
        if (value > (std::numeric_limits<std::uint64_t>::max() - digit) / 10) return std::nullopt;
        value = value * 10 + digit;
    }
    return value;
}

namespace {

// Every value given for a parameter, in request order, under either
// spelling (part 1's lower case, GB/T 18759.6 tables 7-8's capital).
std::vector<const std::string*> values_of(const QueryParams& query, const char* name, const char* gbt_name) {
    std::vector<const std::string*> out;
    for (const char* spelling : {name, gbt_name}) {
        auto [begin, end] = query.equal_range(spelling);
        for (auto it = begin; it != end; ++it) out.push_back(&it->second);
    }
    return out;
}

bool looks_negative_integer(const std::string& text) {
    return text.size() > 1 && text[0] == '-' && parse_unsigned(std::string_view(text).substr(1)).has_value();
}

// An integer parameter: INVALID_REQUEST when it is not one, OUT_OF_RANGE when
// negative or above `max`.
std::optional<MtError> integer(const std::string& text, const char* name, std::uint64_t min, std::uint64_t max, std::uint64_t& out) {
    if (looks_negative_integer(text))
        return MtError{MtErrorCode::out_of_range,
                       std::string("'") + name + "' must be greater than or equal to " + std::to_string(min)};
    auto value = parse_unsigned(text);
    if (!value) {
        if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos)
            return MtError{MtErrorCode::out_of_range, std::string("'") + name + "' is too large"};
        return MtError{MtErrorCode::invalid_request,
                       std::string("'") + name + "' must be a positive integer, not '" + text.substr(0, 64) + "'"};
    }
    if (*value < min)
        return MtError{MtErrorCode::out_of_range,
                       std::string("'") + name + "' must be greater than or equal to " + std::to_string(min)};
    if (*value > max)
        return MtError{MtErrorCode::out_of_range,
                       std::string("'") + name + "' must be less than or equal to " + std::to_string(max)};
    out = *value;
    return std::nullopt;
}

// An integer parameter given once or more: every value must be valid (a
// malformed one is an error even beside a good one, 6.3.4) and all must agree.
std::optional<MtError> one_integer(const QueryParams& query, const char* name, const char* gbt_name, std::uint64_t min,
                                   std::uint64_t max, std::optional<std::uint64_t>& out) {
    for (const std::string* text : values_of(query, name, gbt_name)) {
        std::uint64_t value = 0;
        if (auto e = integer(*text, name, min, max, value)) return e;
        if (out && *out != value)
            return MtError{MtErrorCode::invalid_request, std::string("'") + name + "' is given twice with different values"};
        out = value;
    }
    return std::nullopt;
}

// path: an XPath (part 1 8.3.1). libxml2 reads it up to a NUL byte, so one
// with a NUL in it would be answered as its head: refused instead.
std::optional<MtError> one_path(const QueryParams& query, std::optional<std::string>& out) {
    for (const std::string* text : values_of(query, "path", "Path")) {
        if (text->find('\0') != std::string::npos) return MtError{MtErrorCode::invalid_path, "the path holds a NUL character"};
        if (out && *out != *text) return MtError{MtErrorCode::invalid_request, "'path' is given twice with different values"};
        out = *text;
    }
    return std::nullopt;
}

// Interval and heartbeat are milliseconds; a day is more than any dashboard waits.
constexpr std::uint64_t kMaxMillis = 24ull * 3600 * 1000;

std::optional<MtError> streaming(const QueryParams& query, std::optional<std::chrono::milliseconds>& interval,
                                 std::chrono::milliseconds& heartbeat) {
    std::optional<std::uint64_t> value;
    if (auto e = one_integer(query, "interval", "Interval", 0, kMaxMillis, value)) return e;
    if (value) interval = std::chrono::milliseconds(*value);
    value.reset();
    if (auto e = one_integer(query, "heartbeat", "Heartbeat", 10, kMaxMillis, value)) return e;
    if (value) heartbeat = std::chrono::milliseconds(*value);
    return std::nullopt;
}

}  // namespace

std::optional<MtError> parse_sample_params(const QueryParams& query, std::size_t buffer_size, SampleParams& out) {
    std::optional<std::uint64_t> value;
    if (auto e = one_integer(query, "from", "From", 1, std::numeric_limits<std::uint64_t>::max(), value)) return e;
    if (value) out.from = *value;
    value.reset();
    if (auto e = one_integer(query, "count", "Count", 1, buffer_size, value)) return e;
    if (value) out.count = static_cast<std::size_t>(*value);
    if (auto e = streaming(query, out.interval, out.heartbeat)) return e;
    return one_path(query, out.path);
}

std::optional<MtError> parse_current_params(const QueryParams& query, std::size_t buffer_size, CurrentParams& out) {
    std::optional<std::uint64_t> value;
    if (auto e = one_integer(query, "at", "At", 0, std::numeric_limits<std::uint64_t>::max(), value)) return e;
    out.at = value;
    // GB/T 18759.6 table 7 lists Count for the snapshot too: checked as
    // /sample's count (1..bufferSize), though a snapshot has one value per item.
    value.reset();
    if (auto e = one_integer(query, "count", "Count", 1, buffer_size, value)) return e;
    out.count = value;
    if (auto e = streaming(query, out.interval, out.heartbeat)) return e;
    if (out.at && out.interval) return MtError{MtErrorCode::invalid_request, "'at' and 'interval' cannot be given together"};
    return one_path(query, out.path);
}

std::optional<MtError> check_from(std::uint64_t from, std::uint64_t first, std::uint64_t next) {
    if (from < first)
        return MtError{MtErrorCode::out_of_range,
                       "'from' must be greater than or equal to " + std::to_string(first) + " (firstSequence)"};
    if (from > next)
        return MtError{MtErrorCode::out_of_range,
                       "'from' must be less than or equal to " + std::to_string(next) + " (nextSequence)"};
    return std::nullopt;
}

std::optional<MtError> check_at(std::uint64_t at, std::uint64_t first, std::uint64_t last) {
    if (last < first) return MtError{MtErrorCode::out_of_range, "'at' given while the buffer is empty"};
    if (at < first)
        return MtError{MtErrorCode::out_of_range,
                       "'at' must be greater than or equal to " + std::to_string(first) + " (firstSequence)"};
    if (at > last)
        return MtError{MtErrorCode::out_of_range,
                       "'at' must be less than or equal to " + std::to_string(last) + " (lastSequence)"};
    return std::nullopt;
}

}  // namespace nclink::bridge
