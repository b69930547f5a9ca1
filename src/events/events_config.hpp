// Reads and compares the "events" section of an adapter configuration (docs/configuration.md);
// unknown keys are refused like everywhere else.
#pragma once

#include <nclink/feature_config.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <string>
#include <vector>

namespace nclink::events_detail {

Result<void> read_events_config(const Json& section, EventsConfig& out);

/// Appends to `out` the keys of the section that differ between `a` and `b`,
/// by their dotted path in the file ("events.qos"): its part of what
/// Adapter::reload reports (docs/configuration.md, "Reloading").
void events_config_changes(const EventsConfig& a, const EventsConfig& b, std::vector<std::string>& out);

}  // namespace nclink::events_detail
