// Model file versions (chapter 6, table 2: "形式为 1.x.x") compared and
// raised. The standard's own examples also write "1.3" and "v1.0.1"
// (8.2.5.5), so both are accepted: an optional leading 'v', then numbers
// separated by dots; missing parts count as 0 ("1.3" equals "1.3.0").
//
// Pure functions; thread-safe.
#pragma once

#include <nclink/export.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace nclink {

/// <0 when `a` is older than `b`, 0 when equal, >0 when newer; nullopt when
/// either is not of the form above (then no order can be told).
NCLINK_API std::optional<int> compare_model_versions(std::string_view a, std::string_view b) noexcept;

/// True when `version` has the form above.
NCLINK_API bool is_model_version(std::string_view version) noexcept;

/// The next version after `version`: its last number plus one ("1.0.9" ->
/// "1.0.10", "v1.3" -> "v1.4"). A version not of the form gets ".1" appended,
/// so the result still differs from it (caches compare versions for
/// inequality, 8.2.7.3).
NCLINK_API std::string next_model_version(std::string_view version);

}  // namespace nclink
