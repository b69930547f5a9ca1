// The kinds of configuration file nclink knows, one table entry each: the
// reader that checks a file of that kind, and (by name) its JSON Schema under
// docs/schema/<name>.schema.json, built into the program. `nclink config`
// and the schema tests go through this table, so adding a kind (the bridge's,
// the gateway's) is its schema file plus one entry in config_kinds.cpp.
#pragma once

#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::cli {

struct ConfigKind {
    const char* name;     ///< "adapter": also the schema's file name (docs/schema/adapter.schema.json)
    const char* summary;  ///< for usage texts
    /// The program's own reader on a parsed document (errors carry a JSON pointer).
    Result<void> (*check)(const Json& document);
};

/// Every kind, in a stable order.
const std::vector<ConfigKind>& config_kinds();
const ConfigKind* find_config_kind(std::string_view name);

/// The schemas built into the program (docs/schema/*.schema.json).
struct EmbeddedSchema {
    const char* name;  ///< file name without ".schema.json"
    const char* text;
};
const std::vector<EmbeddedSchema>& embedded_schemas();
/// The parsed schema of a kind; nullopt when none is built in.
std::optional<Json> config_schema(std::string_view kind);

}  // namespace nclink::cli
