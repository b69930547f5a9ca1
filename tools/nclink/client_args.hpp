// Request items as text, in the syntax of the `nclink` command line:
//   query:  ID            ID:{"operation":"get_length"}
//   set:    ID=VALUE      (VALUE is JSON if it parses, else taken as a string)
//           ID:{"value":5,"index":2}   (the full params object)
// and the one-line rendering of results. Pure functions, thread-safe.
#pragma once

#include <nclink/dtu.hpp>
#include <nclink/result.hpp>

#include <string>
#include <string_view>

namespace nclink {

/// "ID" or "ID:{params}". Fails with parameter_missing (empty id) or
/// syntax_error (params not a JSON object).
Result<QueryItem> parse_query_spec(std::string_view spec);

/// "ID=VALUE" -> params {"value": VALUE}; "ID:{params}" -> those params.
/// Whichever of '=' and ':' comes first splits. Fails with parameter_missing
/// (empty id, no '=' or ':') or syntax_error (params not a JSON object).
Result<SetItem> parse_set_spec(std::string_view spec);

/// A JSON value if `text` is one, else `text` as a JSON string.
Json parse_value_text(std::string_view text);

/// The `values` of an OK query result: the single element of a one-element
/// array, else the whole array, as compact JSON.
std::string format_values(const Json& values);

/// "ID = VALUE" or "ID: NG 401 Node not exists".
std::string format_query_result(const QueryResult& result);
/// "ID: OK" or "ID: NG 405 Value type error".
std::string format_set_result(const SetResult& result);

}  // namespace nclink
