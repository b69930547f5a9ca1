// Checks that need the whole index: what the sample channels point at.
#pragma once

#include "model/problems.hpp"
#include "model/read_tree.hpp"

#include <nclink/model.hpp>

#include <vector>

namespace nclink::model_detail {

/// A channel id naming nothing, or something other than a data object, is
/// fatal (the channel cannot be sampled); naming a config object is a
/// conformance problem (6.2.2 note b: configs are never sample sources).
/// A fixed `value` (table 4 note a) that breaks its item's chapter-7 rule
/// (value_rules.hpp): a conformance problem at the value.
void check_fixed_values(const Model& model, Problems& problems);

void check_channel_references(const Model& model, const std::vector<ChannelReference>& refs, Problems& problems);

}  // namespace nclink::model_detail
