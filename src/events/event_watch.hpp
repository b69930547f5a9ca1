// One registration's evaluation: its filters (OR-ed, in order), its trigger,
// and the two values the standard's rules refer to:
//   previous  the value observed last (what "changed" compares with, and the
//             event's oldValue);
//   recorded  the value at the previous event (what `variance` measures from).
//
// A value is evaluated when it is the first one observed (the registration's
// current value, 8.2.27.4: "if the current value already matches, the
// subscriber gets an event") or when it differs from the previous one
// (always: "every time the value changes and still matches"). Repeated equal
// values (a poll or sample row that saw no change) make no event.
//
// Not thread-safe: owned by the events thread.
#pragma once

#include "events/event_filter.hpp"
#include "events/event_trigger.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace nclink::events_detail {

struct EventFiring {
    std::optional<Json> old_value;  ///< absent for the registration's first value
    Json value;
};

class EventWatch {
public:
    EventWatch(std::vector<EventFilter> filters, TriggerType trigger);

    /// Feeds one observed value; returns the event to send, if one fires.
    std::optional<EventFiring> observe(const Json& value);
    /// A once trigger has fired: release the registration.
    bool finished() const noexcept { return trigger_.finished(); }
    /// Values evaluated so far (the first one and every change).
    std::uint64_t evaluations() const noexcept { return evaluations_; }

private:
    std::vector<EventFilter> filters_;
    TriggerState trigger_;
    std::optional<Json> previous_;
    std::optional<Json> recorded_;
    std::uint64_t evaluations_ = 0;
};

}  // namespace nclink::events_detail
