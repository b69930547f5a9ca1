// Helpers shared by the files of src/values/ (not installed).
#pragma once

#include <nclink/values.hpp>

#include <fmt/format.h>

#include <string>
#include <utility>

namespace nclink::values_detail {

template <class... Args>
Error fail(ErrorCode code, fmt::format_string<Args...> format, Args&&... args) {
    return make_error(code, fmt::format(format, std::forward<Args>(args)...));
}

/// Reads a non-negative integer parameter given as a JSON number (integral)
/// or a numeric string. `what` names it in messages. 405 for other types or
/// text, 101 for negative or oversized numbers.
Result<std::size_t> parse_count(const Json& value, std::string_view what);

/// Whether a dict/list item's value has the shape its kind needs (null counts
/// as "not known yet" and fits every kind).
bool fits_kind(const Json& value, DataKind kind) noexcept;

/// Computes the element that results from writing `value` into `element`
/// under the request's offset/length (or plain replacement without them),
/// applying the set type rule. `where` names the element in messages.
Result<Json> patch_element(const Json& element, const Json& value, const std::optional<std::size_t>& offset,
                           const std::optional<std::size_t>& length, const std::string& where);

/// The part of `element` that offset/length select, as patch_element()
/// writes it: code points of a string, elements of an array, bits of an
/// integer (without length: the one bit at offset, 0 or 1).
Result<Json> element_part(const Json& element, const std::optional<std::size_t>& offset, const std::optional<std::size_t>& length,
                          const std::string& where);

}  // namespace nclink::values_detail
