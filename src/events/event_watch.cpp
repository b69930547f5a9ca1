#include "events/event_watch.hpp"

namespace nclink::events_detail {

EventWatch::EventWatch(std::vector<EventFilter> filters, TriggerType trigger) : filters_(std::move(filters)), trigger_(trigger) {}

std::optional<EventFiring> EventWatch::observe(const Json& value) {
    if (trigger_.finished()) return std::nullopt;
    if (previous_ && same_value(*previous_, value)) return std::nullopt;  // nothing changed
    ++evaluations_;
    const Json* previous = previous_ ? &*previous_ : nullptr;
    const Json* recorded = recorded_ ? &*recorded_ : nullptr;
    const bool matched = first_match(filters_, value, previous, recorded).has_value();
    std::optional<EventFiring> out;
    if (trigger_.fire(matched)) {
        out = EventFiring{previous_, value};
        recorded_ = value;
    }
    previous_ = value;
    return out;
}

}  // namespace nclink::events_detail
