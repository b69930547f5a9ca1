// "Did you mean ...?": the closest of a set of known names to a name that is
// not one of them, for error messages (configuration keys, model types and
// units). Pure functions, no state.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::core_detail {

/// Edit distance (insertions, deletions, substitutions, and swaps of two
/// neighbouring characters), compared case-insensitively.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate nearest to `name`, if it is near enough to be a likely typo:
/// a case-insensitive match, one name a prefix of the other, or within an
/// edit distance of about a third of the name's length (at least 1, at most
/// 3). Ties go to the first candidate given.
std::optional<std::string> nearest_name(std::string_view name, const std::vector<std::string_view>& candidates);

}  // namespace nclink::core_detail
