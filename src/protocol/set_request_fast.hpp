// Internal: a Set request (8.2.13) in the plain form applications send,
//   {"@id":"...","guid":"...","values":[{"id":"...","params":{"value":42}},...]}
// read by a direct scan instead of being parsed into a Json tree.
//
// Why: the adapter decodes every Set on the MQTT receive thread (to read its
// @id before queueing it); the tree costs ~1.2 us of a 1-item Set there, the
// scan ~0.2 us (docs/performance.md "Requests").
//
// The contract is that of query_request_fast.hpp: it answers only for
// payloads the tree decoder (read(Json, Tag<SetRequest>)) accepts, and then
// with exactly that decoder's result, Json types included. Anything else (a
// number @id, offset/length, privateInfo, params holding a structure,
// another key, a key twice, an escape) returns nullopt and the caller uses
// the tree decoder, which gives the table-19 answer. decode<SetRequest>(text)
// does exactly that.
#pragma once

#include <nclink/dtu.hpp>

#include <optional>
#include <string_view>

namespace nclink::protocol_detail {

std::optional<SetRequest> plain_decode_set_request(std::string_view payload);

}  // namespace nclink::protocol_detail
