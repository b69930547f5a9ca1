// Chapter 7 vocabularies (tables 7, 8, 10-13) and unit names (tables 10, 11,
// appendix A `unitType`). Constant tables, no state.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace nclink::model_detail {

bool is_device_type(std::string_view type) noexcept;     // table 7
bool is_component_type(std::string_view type) noexcept;  // table 8
bool is_data_type(std::string_view type) noexcept;       // tables 10, 12, 13
bool is_known_unit(std::string_view units) noexcept;     // tables 10, 11, 13, appendix A

/// For a type not in the table: the table entry it most likely meant
/// (case-insensitive match, or a known abbreviation such as SPDL_OVERRIDE).
std::optional<std::string> suggest_data_type(std::string_view type);
std::optional<std::string> suggest_device_type(std::string_view type);
std::optional<std::string> suggest_component_type(std::string_view type);

/// For a type or unit of its own (an extension the standard allows): the
/// standard name it may have meant, by a known common name ("rpm", "SPINDLE")
/// or by spelling distance, for a "did you mean" hint. Looser than suggest_*.
std::optional<std::string> nearest_data_type(std::string_view type);
std::optional<std::string> nearest_device_type(std::string_view type);
std::optional<std::string> nearest_component_type(std::string_view type);
std::optional<std::string> nearest_unit(std::string_view units);

}  // namespace nclink::model_detail
