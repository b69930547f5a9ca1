#include <nclink/error.hpp>

#include <fmt/format.h>

#include <array>
#include <cctype>

namespace nclink {
namespace {

struct ReasonEntry {
    ErrorCode code;
    std::string_view reason;
};

// Table 19, spelled exactly as the standard prints it (including its
// capitalisation, e.g. lower-case "syntax error").
constexpr std::array<ReasonEntry, 27> kReasons{{
    {ErrorCode::success, "Success"},
    {ErrorCode::out_of_range, "Out of Range"},
    {ErrorCode::parameter_missing, "Parameter Missing"},
    {ErrorCode::unavailable, "Unavailable"},
    {ErrorCode::timeout, "Timeout"},
    {ErrorCode::permission_denied, "Permission Denied"},
    {ErrorCode::node_not_exists, "Node not exists"},
    {ErrorCode::no_index, "No index passed in"},
    {ErrorCode::no_key, "No key passed in"},
    {ErrorCode::memory_configured, "Memory configured error"},
    {ErrorCode::value_type, "Value type error"},
    {ErrorCode::unsupported_get_length, "unsupported operation get_length"},
    {ErrorCode::unsupported_get_attributes, "unsupported operation get_attributes"},
    {ErrorCode::unsupported_get_keys, "unsupported operation get_keys"},
    {ErrorCode::arguments_nimiety, "arguments nimiety"},
    {ErrorCode::key_error, "key error"},
    {ErrorCode::attribute_error, "Attribute error"},
    {ErrorCode::syntax_error, "syntax error"},
    {ErrorCode::keys_of_arguments, "keys of arguments error"},
    {ErrorCode::unsupported_terminal_id, "unsupported terminal identifier"},
    {ErrorCode::insufficient_dynamic_sampling, "Insufficient dynamic sampling resources"},
    {ErrorCode::insufficient_event, "Insufficient event resources"},
    {ErrorCode::insufficient_method, "Insufficient method resources"},
    {ErrorCode::method_action_type, "method action type error"},
    {ErrorCode::filter_type, "filter type error"},
    {ErrorCode::trigger_type, "trigger type error"},
    {ErrorCode::filter_arguments_mismatch, "filter type and arguments not matched"},
}};

std::string fold(std::string_view text) {
    std::string out;
    for (char c : text) {
        if (std::isspace(static_cast<unsigned char>(c)) || c == '_') continue;
        out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    }
    return out;
}

}  // namespace

std::string_view reason(ErrorCode code) noexcept {
    for (const auto& entry : kReasons)
        if (entry.code == code) return entry.reason;
    return "Unknown error";
}

std::optional<ErrorCode> error_code_from_int(int value) noexcept {
    for (const auto& entry : kReasons)
        if (to_int(entry.code) == value) return entry.code;
    return std::nullopt;
}

std::optional<ErrorCode> error_code_from_reason(std::string_view text) noexcept {
    for (const auto& entry : kReasons)
        if (entry.reason == text) return entry.code;
    const std::string wanted = fold(text);
    for (const auto& entry : kReasons)
        if (fold(entry.reason) == wanted) return entry.code;
    return std::nullopt;
}

std::string Error::describe() const {
    const std::string_view what = to_int(code) < 0 ? std::string_view("vendor error") : reason(code);
    if (message.empty()) return fmt::format("{} {}", to_int(code), what);
    return fmt::format("{} {}: {}", to_int(code), what, message);
}

}  // namespace nclink
