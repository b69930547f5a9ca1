// Where a JSON pointer (RFC 6901) points to in the text of a JSON document,
// as a line and column, so configuration errors can name the spot in the
// file (docs/configuration.md, "Checking a file").
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace nclink::core_detail {

/// 1-based line and column; the column counts characters (UTF-8 code points).
struct TextPosition {
    std::size_t line = 1;
    std::size_t column = 1;
};

/// The line and column of byte `offset` of `text` (clamped to its end).
TextPosition position_of_offset(std::string_view text, std::size_t offset);

/// The position of what `pointer` names in `text`, which must be valid JSON:
/// for an object member its key (the opening quote), for an array element or
/// the whole document the value. nullopt when the pointer names nothing in
/// the text. With duplicate keys the last one counts, as when parsing.
std::optional<TextPosition> locate_pointer(std::string_view text, std::string_view pointer);

}  // namespace nclink::core_detail
