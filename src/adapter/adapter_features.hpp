// The features the adapter composes beside Query/Set/Probe (sampling,
// methods, events; the contract is feature/feature.hpp, which names none of
// them). The functions below are the one place of the adapter that names
// each: a new feature adds its configuration section, its factory and its
// drops there. Each feature owns its section (reading it, comparing it on
// reload) and its drop causes; these functions only list them.
#pragma once

#include "core/config_reader.hpp"
#include "feature/feature.hpp"

#include <nclink/adapter_config.hpp>

#include <memory>
#include <string>
#include <vector>

namespace nclink::detail {

/// Reads the features' sections of a configuration file (docs/configuration.md).
Result<void> read_feature_sections(ConfigReader& top, AdapterConfig& out);

/// Appends the keys of the features' sections that differ (adapter_reload.hpp).
void feature_config_changes(const AdapterConfig& a, const AdapterConfig& b, std::vector<std::string>& out);

/// The features, in start order (stopped in reverse), each given its own section.
std::vector<std::unique_ptr<Feature>> make_features(FeatureHost& host, const AdapterConfig& config);

/// Every feature's drop causes read from a statistics snapshot's "features"
/// object (AdapterStats::features): what their add_drops() count live.
void feature_drops_from_stats(const Json& features, DropCounts& out);

}  // namespace nclink::detail
