// The test record of table C.1 as Markdown (for people) and JSON (for tools).
#pragma once

#include "conform/record.hpp"

#include <nclink/json.hpp>

#include <string>

namespace nclink::conform {

/// Markdown laid out like table C.1: basic information, verdict, connection
/// test, model-file object counts, interface tests (supported / result), then
/// the test process record with the evidence of every failure.
std::string render_markdown(const TestRecord& record);

/// The same content as one JSON object:
/// {"standard","record","tool","basic":{...},"verdict","counts":{...},
///  "objects":{...}|null,"items":[{key,title,c1_row,clause,c1_mandatory,
///  required,supported,outcome,summary,notes,evidence:[{note,topic,dtu}]}]}
/// `supported` is true/false, or null when the item was skipped.
Json render_json(const TestRecord& record);

}  // namespace nclink::conform
