// Walks a parsed probe document, checks every object against chapter 6 and
// the chapter 7 vocabularies, and feeds the objects to a ModelBuilder.
#pragma once

#include "model/model_builder.hpp"
#include "model/problems.hpp"

#include <nclink/json.hpp>

#include <string>
#include <vector>

namespace nclink::model_detail {

/// A channel's `ids` as written, kept for the cross checks that need the
/// whole index (the items a channel names may be defined after it).
struct ChannelReference {
    std::string channel_id;
    std::string id;       ///< the data item named
    std::string pointer;  ///< of the `ids` entry
};

struct ReadOutcome {
    std::vector<ChannelReference> channel_references;
};

/// `document` may be any JSON value; problems are reported, never thrown.
ReadOutcome read_document(const Json& document, Problems& problems, ModelBuilder& builder);

}  // namespace nclink::model_detail
