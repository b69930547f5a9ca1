// Access control (5.2.2, table 19 code 301 b): which request kinds need which
// right, and what an application may do on an adapter.
#pragma once

#include <nclink/agent.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>
#include <nclink/topics.hpp>

#include <optional>
#include <string>
#include <vector>

namespace nclink::agent_detail {

/// The right a request kind needs; std::nullopt for kinds that are not
/// requests to an adapter.
std::optional<AccessRight> required_right(TopicKind request_kind) noexcept;

/// Every request kind the agent watches (both spellings come from the topics).
const std::vector<TopicKind>& adapter_request_kinds();

/// The rights of application `ex` on adapter `dev` (precedence in agent.hpp).
unsigned rights_of(const AccessPolicy& policy, const std::string& ex, const std::string& dev);

/// True when `ex` may do `right` on `dev`.
inline bool allowed(const AccessPolicy& policy, const std::string& ex, const std::string& dev, AccessRight right) {
    return (rights_of(policy, ex, dev) & right) != 0;
}

/// ["read","set","method","watch"], "all" (read, set, method) or "none" -> bits; 405 for anything else,
/// naming `where` (dotted, for the message) and `pointer` (Error::pointer).
Result<unsigned> parse_rights(const Json& value, const std::string& where, const std::string& pointer = {});
/// The names of the bits, e.g. ["read","set"].
std::vector<std::string> right_names(unsigned rights);

}  // namespace nclink::agent_detail
