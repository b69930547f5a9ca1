// Shared DTU machinery: the key reader behind every decoder (102/413/405
// classification), the response status and the key writers.
#include "protocol/dtu_codec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace nclink {

ResponseStatus::ResponseStatus(const Error& failure) {
    if (failure.code == ErrorCode::success) return;
    ok = false;
    const int number = to_int(failure.code);
    if (error_code_from_int(number)) {
        reason = std::string(nclink::reason(failure.code));
        error = number;
    } else if (number < 0) {
        // Table 19: codes below 0 and their reasons are the user's (a vendor's).
        reason = failure.message.empty() ? fmt::format("vendor error {}", number) : failure.message;
        error = number;
    } else {
        // A positive code table 19 does not define: docs/wire.md, "Vendor errors".
        reason = std::string(nclink::reason(ErrorCode::unavailable));
        error = to_int(ErrorCode::unavailable);
    }
}

ResponseStatus ResponseStatus::failure(std::string reason_text, std::optional<int> error_number) {
    ResponseStatus status;
    status.ok = false;
    status.reason = std::move(reason_text);
    status.error = error_number;
    return status;
}

std::optional<ErrorCode> ResponseStatus::error_code() const noexcept {
    if (!error) return std::nullopt;
    return error_code_from_int(*error);
}

MessageId peek_message_id(std::string_view payload) {
    try {
        if (!protocol_detail::depth_ok(payload)) return std::nullopt;
        const Json dtu = Json::parse(payload.begin(), payload.end(), nullptr, false);
        if (!dtu.is_object()) return std::nullopt;
        const auto it = dtu.find("@id");
        if (it == dtu.end() || it->is_structured()) return std::nullopt;
        return *it;
    } catch (...) {
        return std::nullopt;
    }
}

namespace protocol_detail {

void fail(ErrorCode code, std::string message) { throw DecodeFailure{make_error(code, std::move(message))}; }

Reader::Reader(const Json& object, std::initializer_list<std::string_view> known, std::string_view what)
    : object_(object), known_(known), what_(what) {}

const Json* Reader::find(std::string_view key) const {
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
}

const Json& Reader::require(std::string_view key) const {
    const Json* value = find(key);
    if (!value) missing(key);
    return *value;
}

void Reader::missing(std::string_view key) const {
    // A plain omission is 102; if the object also carries keys this DTU does
    // not define, the sender most likely used the wrong keys (e.g. "values"
    // instead of "ids"): 413.
    for (const auto& item : object_.items()) {
        const std::string_view name = item.key();
        if (std::find(known_.begin(), known_.end(), name) == known_.end())
            fail(ErrorCode::keys_of_arguments, fmt::format("{}: \"{}\" missing, unknown key \"{}\"", what_, key, name));
    }
    fail(ErrorCode::parameter_missing, fmt::format("{}: \"{}\" missing", what_, key));
}

void Reader::wrong_type(std::string_view key, std::string_view expected) const {
    const Json* value = find(key);
    fail(ErrorCode::value_type,
         fmt::format("{}: \"{}\" must be {}, got {}", what_, key, expected, value ? value->type_name() : "nothing"));
}

std::string Reader::require_string(std::string_view key) const {
    const Json& value = require(key);
    if (!value.is_string()) wrong_type(key, "a string");
    return value.get<std::string>();
}

std::optional<std::string> Reader::optional_string(std::string_view key) const {
    const Json* value = find(key);
    if (!value) return std::nullopt;
    if (!value->is_string()) wrong_type(key, "a string");
    return value->get<std::string>();
}

double Reader::require_number(std::string_view key) const {
    const Json& value = require(key);
    if (!value.is_number()) wrong_type(key, "a number");
    return value.get<double>();
}

std::optional<double> Reader::optional_number(std::string_view key) const {
    const Json* value = find(key);
    if (!value) return std::nullopt;
    if (!value->is_number()) wrong_type(key, "a number");
    return value->get<double>();
}

namespace {

std::optional<std::int64_t> integer_of(const Json& value) {
    if (value.is_number_integer()) {
        if (value.is_number_unsigned() &&
            value.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
            return std::nullopt;
        return value.get<std::int64_t>();
    }
    if (value.is_number_float()) {
        const double d = value.get<double>();
        // 2^63 is exactly representable; anything from there up does not fit.
        if (!std::isfinite(d) || d != std::floor(d) || d < -9223372036854775808.0 || d >= 9223372036854775808.0)
            return std::nullopt;
        return static_cast<std::int64_t>(d);
    }
    if (value.is_string()) {
        const auto& text = value.get_ref<const std::string&>();
        std::int64_t out = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
        if (ec != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
        return out;
    }
    return std::nullopt;
}

}  // namespace

std::optional<std::int64_t> Reader::optional_integer(std::string_view key) const {
    const Json* value = find(key);
    if (!value) return std::nullopt;
    auto out = integer_of(*value);
    if (!out) wrong_type(key, "an integer (number or numeric string)");
    return out;
}

std::int64_t Reader::require_integer(std::string_view key) const {
    require(key);
    return *optional_integer(key);
}

const Json& Reader::require_array(std::string_view key) const {
    const Json& value = require(key);
    if (!value.is_array()) wrong_type(key, "an array");
    return value;
}

std::optional<Json> Reader::optional_any(std::string_view key) const {
    const Json* value = find(key);
    if (!value) return std::nullopt;
    return *value;
}

MessageId Reader::message_id() const {
    const Json* value = find("@id");
    if (!value) return std::nullopt;
    // Any scalar is echoed verbatim; a structure cannot be a message id.
    if (value->is_structured()) wrong_type("@id", "a scalar");
    return *value;
}

ResponseStatus Reader::status() const {
    ResponseStatus status;
    const std::string code = require_string("code");
    // Liberal: "ok"/"Ok" is OK; any other code is a failure.
    status.ok = code.size() == 2 && (code[0] == 'O' || code[0] == 'o') && (code[1] == 'K' || code[1] == 'k');
    status.reason = optional_string("reason");
    if (has("error")) {
        const auto number = optional_integer("error");
        if (*number < std::numeric_limits<int>::min() || *number > std::numeric_limits<int>::max()) wrong_type("error", "an int");
        status.error = static_cast<int>(*number);
    }
    return status;
}

std::optional<ResponseStatus> Reader::optional_status() const {
    if (!has("code")) return std::nullopt;
    return status();
}

const Json& expect_object(const Json& value, ErrorCode code, std::string_view what) {
    if (!value.is_object()) fail(code, fmt::format("{} must be a JSON object, got {}", what, value.type_name()));
    return value;
}

Json probe_value(const Json& value, std::string_view what) {
    if (value.is_object()) return value;
    if (value.is_string()) {
        const auto& text = value.get_ref<const std::string&>();
        if (!depth_ok(text)) fail(ErrorCode::syntax_error, fmt::format("{}: probe nested too deeply", what));
        Json parsed = Json::parse(text, nullptr, false);
        if (parsed.is_discarded()) fail(ErrorCode::syntax_error, fmt::format("{}: probe string is not JSON", what));
        if (!parsed.is_object()) fail(ErrorCode::value_type, fmt::format("{}: probe is not a JSON object", what));
        return parsed;
    }
    fail(ErrorCode::value_type, fmt::format("{}: probe must be an object or a string holding one", what));
}

bool depth_ok(std::string_view payload) noexcept {
    int depth = 0;
    bool in_string = false;
    bool escaped = false;
    for (const char c : payload) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
            continue;
        }
        if (c == '"') in_string = true;
        else if (c == '[' || c == '{') {
            if (++depth > max_payload_depth) return false;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return true;
}

Json parse_payload(std::string_view payload) {
    if (!depth_ok(payload)) fail(ErrorCode::syntax_error, "payload nested too deeply");
    Json dtu = Json::parse(payload.begin(), payload.end(), nullptr, false);
    if (dtu.is_discarded()) fail(ErrorCode::syntax_error, "payload is not valid JSON");
    if (!dtu.is_object()) fail(ErrorCode::syntax_error, "payload is not a JSON object");
    return dtu;
}

void put_msg_id(Json& out, const MessageId& id) {
    if (id) out["@id"] = *id;
}

void put_if(Json& out, const char* key, const std::string& value) {
    if (!value.empty()) out[key] = value;
}

void put_if(Json& out, const char* key, const std::optional<Json>& value) {
    if (value) out[key] = *value;
}

void put_if(Json& out, const char* key, const std::optional<std::string>& value) {
    if (value) out[key] = *value;
}

void put_status(Json& out, const ResponseStatus& status) {
    out["code"] = status.code();
    if (status.reason) out["reason"] = *status.reason;
    if (status.error) out["error"] = *status.error;
}

Json number_json(double value) {
    if (std::isfinite(value) && value == std::floor(value) && std::fabs(value) < 9007199254740992.0)
        return static_cast<std::int64_t>(value);
    return value;
}

}  // namespace protocol_detail
}  // namespace nclink
