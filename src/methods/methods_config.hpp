// Reads the "methods" section of an adapter configuration (docs/configuration.md);
// unknown keys are refused like everywhere else.
#pragma once

#include <nclink/feature_config.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

namespace nclink::detail {

Result<void> read_methods_config(const Json& section, MethodsConfig& out);

}  // namespace nclink::detail
