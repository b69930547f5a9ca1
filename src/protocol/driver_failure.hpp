// How a failure a driver reported goes on the wire (docs/wire.md, "Vendor
// errors"): the status keys of table 20 from the code, the vendor's words in
// the item's privateInfo. One rule for Query (8.2.12), Set (8.2.14) and
// Method/Result (8.2.24), so MES finds the vendor's reason in one place.
#pragma once

#include <nclink/dtu_common.hpp>

#include <optional>

namespace nclink::protocol_detail {

struct WireFailure {
    ResponseStatus status;             ///< NG, error and reason per table 19
    std::optional<Json> private_info;  ///< {"message": ...} when there is text to carry
};

/// - a table-19 code: `error` = the code, `reason` = its table-19 string
///   (the table fixes it), privateInfo {"message": error.message} if any;
/// - a code below 0 (table 19: the user's): `error` = the code, `reason` =
///   the vendor's text ("vendor error <n>" when it gave none), and the text
///   again in privateInfo;
/// - any other code: 202 Unavailable, privateInfo {"message": "vendor error
///   <n>: <text>"} (the number survives in the text).
WireFailure driver_failure(const Error& error);

}  // namespace nclink::protocol_detail
