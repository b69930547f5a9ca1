// Reads the "sampling" section of an adapter configuration (docs/configuration.md);
// unknown keys are refused like everywhere else.
#pragma once

#include <nclink/feature_config.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

namespace nclink::detail {

Result<void> read_sampling_config(const Json& section, SamplingConfig& out);

}  // namespace nclink::detail
