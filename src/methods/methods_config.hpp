// Reads and compares the "methods" section of an adapter configuration (docs/configuration.md);
// unknown keys are refused like everywhere else.
#pragma once

#include <nclink/feature_config.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <string>
#include <vector>

namespace nclink::methods_detail {

Result<void> read_methods_config(const Json& section, MethodsConfig& out);

/// Appends to `out` the keys of the section that differ between `a` and `b`,
/// by their dotted path in the file ("methods.qos"): its part of what
/// Adapter::reload reports (docs/configuration.md, "Reloading").
void methods_config_changes(const MethodsConfig& a, const MethodsConfig& b, std::vector<std::string>& out);

}  // namespace nclink::methods_detail
