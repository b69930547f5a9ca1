// Checking one Register/Event request (8.2.27) against the model: what the
// registration watches (a data item as a whole, one dict value by `key`, or
// one list element by `index`), with which filters and trigger.
//
// Errors (table 19), in the order they are checked:
//   401 Node not exists   the id is not a data item of this device
//   409 arguments nimiety both key and index, `index` on a non-list or `key`
//                         on a non-dict item
//   403 No key passed in  a dict item without `key`
//   402 No index passed in  a list item without `index`
//   101 Out of Range      a negative index
//   419 / 421             a bad filter (event_filter.hpp), the first one decides
//   420 trigger type error  triggerType not always/normal/once
// When the current value is known, extract_element() adds 410 key error for a
// key the dict does not hold and 101 for an index past the list's end.
// Pure functions, thread-safe.
#pragma once

#include "events/event_filter.hpp"
#include "events/event_trigger.hpp"

#include <nclink/data_kind.hpp>
#include <nclink/dtu.hpp>
#include <nclink/model.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace nclink::events_detail {

struct EventSpec {
    std::string item;  ///< data item id
    DataKind kind = DataKind::single;
    std::optional<std::string> key;    ///< dict element
    std::optional<std::size_t> index;  ///< list element
    std::vector<EventFilter> filters;  ///< never empty (change by default)
    TriggerType trigger = TriggerType::always;
};

/// `item` is the model's data object for request.id (nullptr when there is none).
Result<EventSpec> validate_registration(const EventRegisterRequest& request, const DataObject* item);

/// The watched element of the item's whole value (the value itself for a
/// whole-item registration). 410 when the dict lacks the key, 101 when the
/// list is too short, 202 when the value is not a dict/list as the model says.
Result<Json> extract_element(const EventSpec& spec, const Json& whole);

}  // namespace nclink::events_detail
