#include "agent/terminal_id.hpp"

#include <fmt/format.h>

#include <string>

namespace nclink::agent_detail {
namespace {

// Length of the UTF-8 sequence starting at `lead`, 0 if it cannot start one.
std::size_t utf8_length(unsigned char lead) {
    if (lead < 0x80) return 1;
    if ((lead >> 5) == 0x6) return 2;
    if ((lead >> 4) == 0xE) return 3;
    if ((lead >> 3) == 0x1E) return 4;
    return 0;
}

bool valid_utf8(std::string_view text) {
    for (std::size_t i = 0; i < text.size();) {
        const std::size_t n = utf8_length(static_cast<unsigned char>(text[i]));
        if (n == 0 || i + n > text.size()) return false;
        for (std::size_t k = 1; k < n; ++k)
            if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return false;
        i += n;
    }
    return true;
}

Error refuse(std::string_view id, std::string_view why) {
    return make_error(ErrorCode::unsupported_terminal_id, fmt::format("terminal id '{}': {}", id, why));
}

}  // namespace

Result<TerminalIdRule> TerminalIdRule::make(const RegistrationPolicy& policy) {
    TerminalIdRule rule;
    rule.max_length_ = policy.max_id_length;
    if (!policy.id_pattern.empty()) {
        try {
            rule.pattern_ = std::make_shared<const std::regex>(policy.id_pattern, std::regex::ECMAScript);
        } catch (const std::regex_error& e) {
            return make_error(ErrorCode::value_type,
                              fmt::format("configuration: registration.id_pattern is not a regex: {}", e.what()));
        }
    }
    return rule;
}

Result<void> TerminalIdRule::check(std::string_view id) const {
    if (id.empty()) return refuse(id, "empty");
    if (id.size() > max_length_) return refuse(id, fmt::format("longer than {} bytes", max_length_));
    if (!valid_utf8(id)) return refuse("(binary)", "not UTF-8");
    if (id.front() == '$') return refuse(id, "starts with '$' (reserved by brokers)");
    for (char c : id) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '/' || c == '+' || c == '#') return refuse(id, "contains a topic separator or wildcard");
        if (u < 0x20 || u == 0x7F || c == ' ') return refuse(id, "contains a control character or space");
    }
    if (pattern_ && !std::regex_match(id.begin(), id.end(), *pattern_))
        return refuse(id, "does not match registration.id_pattern");
    return ok_result();
}

}  // namespace nclink::agent_detail
