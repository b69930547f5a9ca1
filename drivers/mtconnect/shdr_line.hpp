// One line of SHDR, the adapter protocol of an MTConnect agent (MTConnect
// 1.4 part 1, the adapter's "simple hierarchical data representation"),
// read from the protocol's description:
//   2024-01-01T00:00:00.123Z|Xact|12.5|mode|AUTOMATIC
//   2024-01-01T00:00:00.123Z|mill:system|fault|1001|HIGH||Spindle overload
//   2024-01-01T00:00:00.123Z|msg|E17|Door open
//   * PONG 10000
// - fields are split at '|'; a field starting with '"' runs to the '"'
//   followed by '|' or the end of the line, a backslash in it takes the next
//   character literally; fields are trimmed of spaces;
// - the first field is the timestamp, then key|value pairs, several per line;
// - a key "device:item" names the device (its uuid or name) before the item;
// - a CONDITION takes level|native_code|native_severity|qualifier|message,
//   a MESSAGE native_code|text: after an item of several fields the rest of
//   the line is not read (one multi-field item per line);
// - a line starting with '*' is a protocol command ("* PONG 10000").
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace nclink::mtconnect {

/// The fields of a data line, split and unquoted.
std::vector<std::string> shdr_fields(std::string_view line);

/// "* PONG 10000" -> 10000; -1 when the line is no PONG (or its number is bad).
long long shdr_pong_ms(std::string_view line);

/// "dev:item" -> {"dev", "item"}; "item" -> {"", "item"}.
std::pair<std::string, std::string> shdr_split_key(const std::string& key);

}  // namespace nclink::mtconnect
