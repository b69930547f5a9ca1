// Checks the `args` of a Method/Call (8.2.22, table 43) against what the
// METHOD object of the model declares (6.2.7, table 6), before any driver
// call. The model's `args` declares the parameters:
//   object  {"source": "/gcodes/O1", ...}  every key is a parameter the call
//           must give (the values are examples, as in the standard's 6.2.7
//           example, whose 8.2.22 call gives every key);
//   array   ["source", {"name": "mode", "default": "push"},
//            {"name": "note", "optional": true}]  names are required unless
//           the entry has "optional": true or a "default" (filled in);
//   absent/null  nothing declared: any args object passes unchecked.
#pragma once

#include <nclink/json.hpp>
#include <nclink/model.hpp>
#include <nclink/result.hpp>

#include <optional>

namespace nclink::methods_detail {

/// The args object to hand the driver ({} when the call gave none), or
///   405 Value type error    the call's args is not an object;
///   102 Parameter Missing   a required parameter is absent (all named);
///   409 arguments nimiety   a parameter the method does not declare (all named).
/// Pure; thread-safe.
Result<Json> check_method_args(const Method& method, const std::optional<Json>& call_args);

}  // namespace nclink::methods_detail
