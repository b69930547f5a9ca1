// Reads and compares the "sampling" section of an adapter configuration (docs/configuration.md);
// unknown keys are refused like everywhere else.
#pragma once

#include <nclink/feature_config.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <string>
#include <vector>

namespace nclink::sampling_detail {

Result<void> read_sampling_config(const Json& section, SamplingConfig& out);

/// Appends to `out` the keys of the section that differ between `a` and `b`,
/// by their dotted path in the file ("sampling.qos"): its part of what
/// Adapter::reload reports (docs/configuration.md, "Reloading").
void sampling_config_changes(const SamplingConfig& a, const SamplingConfig& b, std::vector<std::string>& out);

}  // namespace nclink::sampling_detail
