// Terminal identifiers (8.1.4): which ids the agent accepts at registration.
#pragma once

#include <nclink/agent.hpp>
#include <nclink/result.hpp>

#include <memory>
#include <regex>
#include <string_view>

namespace nclink::agent_detail {

/// Checks ids against the registration policy. A valid id is one MQTT topic
/// level (it is the last level of request and response topics): non-empty,
/// at most max_id_length bytes, valid UTF-8, no '/', '+', '#', control
/// characters or white space, not starting with '$' (reserved by brokers),
/// and matching id_pattern when one is set.
class TerminalIdRule {
public:
    /// Fails (405) when id_pattern is not a valid ECMAScript regex.
    static Result<TerminalIdRule> make(const RegistrationPolicy& policy);

    /// 414 unsupported terminal identifier, with the reason in the message.
    Result<void> check(std::string_view id) const;

private:
    std::size_t max_length_ = 128;
    std::shared_ptr<const std::regex> pattern_;
};

}  // namespace nclink::agent_detail
