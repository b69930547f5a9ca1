// Event filters of GB/T 41970-2022 8.2.27.4 (table 48, figure 16): which
// values of a watched element make an event.
//
//   change   the value changed                     (default when none given)
//   equal    value == `value` (number, string or boolean)
//   range    `from` < value < `to` (both bounds excluded; numbers)
//   less     value < `value`  (number)
//   greater  value > `value`  (number)
//   include  value is one of `values` (numbers, strings, booleans)
//
// `variance` (change/range/less/greater only) adds a second condition:
// |value - recorded| >= variance, where `recorded` is the value at the
// previous event of the registration; not checked for its first event.
//
// Pure functions on values, no state: the registration (event_watch.hpp)
// keeps the previous and recorded values. Thread-safe.
#pragma once

#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <optional>
#include <string_view>
#include <vector>

namespace nclink::events_detail {

enum class FilterType { change, equal, range, less, greater, include };

std::string_view to_string(FilterType type) noexcept;
/// "change", ... (also in any letter case); std::nullopt for other names.
std::optional<FilterType> filter_type_from_string(std::string_view name) noexcept;

struct EventFilter {
    FilterType type = FilterType::change;
    Json value;                      ///< equal, less, greater
    double from = 0;                 ///< range
    double to = 0;                   ///< range
    std::vector<Json> values;        ///< include
    std::optional<double> variance;  ///< change, range, less, greater
};

/// Parses one filter object of `filters`:
///   419 filter type error  - `type` absent, not a string, or not one of the six;
///   421 filter type and arguments not matched - a key the type does not take
///       (e.g. `from` on change, `variance` on equal), a required argument
///       missing, or an argument of the wrong JSON type (a string `value` for
///       less, a negative `variance`, an array `value` for equal...).
Result<EventFilter> parse_filter(const Json& filter);

/// The filters of a registration: absent or empty means one change filter
/// (8.2.27.4). The first bad filter decides the error.
Result<std::vector<EventFilter>> parse_filters(const std::optional<std::vector<Json>>& filters);

/// The filter's own condition for `value`. `previous` is the value observed
/// before this one (null pointer when there was none: at registration, where
/// `change` therefore does not hold). Values of the wrong kind never match
/// (a string is never in a range).
bool condition_holds(const EventFilter& filter, const Json& value, const Json* previous);

/// The variance condition: true without a variance, without a recorded value
/// (first event), or when value or recorded is not a number (a variance only
/// measures numbers); else |value - recorded| >= variance.
bool variance_holds(const EventFilter& filter, const Json& value, const Json* recorded);

/// condition_holds && variance_holds.
bool filter_matches(const EventFilter& filter, const Json& value, const Json* previous, const Json* recorded);

/// Index of the first filter that matches (filters are OR-ed in order, and
/// one evaluation makes at most one event), or std::nullopt.
std::optional<std::size_t> first_match(const std::vector<EventFilter>& filters, const Json& value, const Json* previous,
                                       const Json* recorded);

/// Equality of event values: numbers compare by value (1 == 1.0), everything
/// else as JSON.
bool same_value(const Json& a, const Json& b);

}  // namespace nclink::events_detail
