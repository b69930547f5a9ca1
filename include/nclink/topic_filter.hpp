// MQTT topic-filter matching, used by the transports, the client and the
// topic tables of the protocol.
#pragma once

#include <nclink/export.hpp>
#include <string_view>

namespace nclink {

/// MQTT topic-filter matching with `+` (one level) and `#` (the rest, last
/// level only, including the parent level: "a/#" matches "a"), MQTT 3.1.1
/// section 4.7. Topics starting with `$` do not match filters starting with a
/// wildcard. Thread-safe, allocation-free.
NCLINK_API bool topic_matches(std::string_view filter, std::string_view topic) noexcept;

}  // namespace nclink
