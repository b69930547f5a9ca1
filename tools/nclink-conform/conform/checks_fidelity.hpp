// Checks of the rules an adapter most often bends while looking right: the
// table-19 reason of an NG, the `id` of a refused registration, values
// against chapter 7, the appendix A request forms, the version round trip
// and the Set echo of 8.2.14. Pure functions like checks.hpp; the runner
// (runner_fidelity.cpp) feeds them what came off the wire.
#pragma once

#include "conform/checks.hpp"

#include <nclink/value_rules.hpp>

namespace nclink::conform {

/// Table 20: on NG, `reason` is the table-19 string of `error` (compared
/// without case and surrounding space: the standard's own example writes
/// " Unavailable"), a table-19 string at all when `error` is absent, and
/// free only for user codes (< 0) or DEV_UNREACHABLE (8.3.4).
Problems check_table19_reason(const Json& status);

/// Tables 39 and 49: `id` is present (a string) in every Register/Sample and
/// Register/Event answer, also a refusal.
Problems check_id_in_refusal(const Json& dtu, std::string_view table);

/// The whole value of item `id` (as a whole-item Query or a Sample column
/// answers it) against its chapter-7 rule (value_rules.hpp).
Problems check_value_rule(const ValueRules& rules, const std::string& id, const Json& value);

/// An answer to a request form appendix A or 8.2.11/8.2.13 defines:
/// refused as malformed (412 syntax error, 413 keys of arguments error) it
/// says the adapter does not know the form.
Problems check_form_understood(const Json& entry, std::string_view form);

/// 8.2.5/8.2.8: the version Probe/Version announces is the device version
/// of the model Probe/Query returns, as written (`expected` = what the
/// tester set with Probe/Set, "" = not checked).
Problems check_version_round_trip(std::string_view announced, std::string_view probed, std::string_view expected);

/// 8.2.14 examples: a Set result echoes the request's params that say what
/// was done (operation, key/keys, index/indexes, offset, length), never the
/// value written; `request_params` is the item's params as sent (offset and
/// length given beside them folded in).
Problems check_set_echo(const Json& result, const Json& request_params);

}  // namespace nclink::conform
