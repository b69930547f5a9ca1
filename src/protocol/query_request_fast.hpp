// Internal: a Query request (8.2.11) decoded straight from its text, in one
// streaming pass that builds no Json tree for the request's skeleton.
//
// Why: the tree costs most of a large Query's time in the adapter (a
// 100-item request: ~45 us to parse into a tree and read it, ~12-20 us to
// stream it through nlohmann's SAX, a few us to scan its plain form;
// docs/performance.md "Requests"), and the adapter reads every request's @id
// on the MQTT receive thread before queueing it.
//
// The contract that keeps it safe: it answers only for payloads the tree
// decoder (read(Json, Tag<QueryRequest>)) accepts, and then with exactly
// that decoder's result. Everything else (bad JSON, nesting beyond
// max_payload_depth, a missing or mistyped key, a key given twice) returns
// nullopt, and the caller falls back to the tree decoder, which gives the
// table-19 answer with its message. decode<QueryRequest>(string_view) does
// exactly that, so callers of the public API see no difference but speed.
#pragma once

#include <nclink/dtu.hpp>

#include <optional>
#include <string_view>

namespace nclink::protocol_detail {

std::optional<QueryRequest> fast_decode_query_request(std::string_view payload);

/// The first attempt of fast_decode_query_request(), under the same
/// contract: only the plain form applications send (string "@id" and
/// "guid", ids entries with "id" alone, printable ASCII without escapes),
/// read by a direct scan; nullopt for anything else. Exposed for its tests.
std::optional<QueryRequest> plain_decode_query_request(std::string_view payload);

}  // namespace nclink::protocol_detail
