// `nclink config check`: a configuration file read by the program's own
// reader, every problem located by JSON pointer and line:column. Pure (no
// printing), so the unit tests drive it directly.
#pragma once

#include "config_kinds.hpp"

#include <nclink/error.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::cli {

struct ConfigProblem {
    std::string pointer;               ///< JSON pointer of the key or value ("" = the whole document)
    std::size_t line = 0, column = 0;  ///< 1-based; 0 = not located
    ErrorCode code = ErrorCode::syntax_error;
    std::string message;  ///< "broker.uri: unknown key; did you mean \"url\"? (valid keys: ...)"
};

struct ConfigCheck {
    const ConfigKind* kind = nullptr;  ///< null when the text is not JSON or the kind cannot be told
    bool kind_guessed = false;
    std::vector<ConfigProblem> problems;
    /// Set instead of problems when the kind could not be told from the
    /// content (a usage matter: give --kind).
    std::string undecided;
    bool ok() const { return kind != nullptr && problems.empty() && undecided.empty(); }
};

/// The kind a document's top-level keys belong to: the one kind whose schema
/// knows every key, else the one that knows the most. Empty with `why` set
/// when that is not one kind.
const ConfigKind* guess_config_kind(const Json& document, std::string& why);

/// Checks `text` as a configuration of `kind` (guessed when null). Every
/// problem the reader finds is reported: after each one the offending key is
/// set aside and the rest is read again.
ConfigCheck check_config_text(std::string_view text, const ConfigKind* kind);

}  // namespace nclink::cli
