// Turning NC-Link ids and names into the identifier forms MTConnect's schema
// accepts (xs:ID, xs:NMTOKEN, the x:NAME extension pattern).
#pragma once

#include <string>
#include <string_view>

namespace nclink::mapping_detail {

/// An xs:NMTOKEN form of a name for MTConnect `name` attributes: surrounding
/// white space trimmed, every character that is not an ASCII name character
/// ([A-Za-z0-9._:-]), a Latin-1 letter or a CJK unified ideograph
/// (U+4E00-U+9FA5) replaced by '_'. "" stays "".
std::string nmtoken(std::string_view name);

/// The MTConnect extension form "x:NAME" (pattern [a-ln-z]:[A-Z_0-9]+) of an
/// NC-Link type: upper-cased, other characters as '_'; "x:UNKNOWN" for "".
std::string extension_name(std::string_view type);

/// True for an xs:NCName of ASCII letters, digits, '.', '-', '_' starting with a letter.
bool is_ascii_ncname(std::string_view text) noexcept;

}  // namespace nclink::mapping_detail
