// Event triggers of GB/T 41970-2022 8.2.27.4 (`triggerType`, table 48): when
// a matching value makes an event.
//
//   always  every evaluation whose value matches (the first match, and every
//           change that still matches);
//   normal  only on the transition from not matching to matching (the first
//           match counts as one: before it nothing matched);
//   once    the first match only; then the event is released.
//
// All three also fire at registration when the current value matches
// (the registration's first evaluation starts "not matching").
// Not thread-safe: one TriggerState per registration, used by one thread.
#pragma once

#include <nclink/result.hpp>

#include <optional>
#include <string_view>

namespace nclink::events_detail {

enum class TriggerType { always, normal, once };

std::string_view to_string(TriggerType type) noexcept;
/// "always", "normal", "once" (also in any letter case); std::nullopt otherwise.
std::optional<TriggerType> trigger_type_from_string(std::string_view name) noexcept;
/// As above, as a Result: 420 trigger type error for anything else.
Result<TriggerType> parse_trigger(std::string_view name);

class TriggerState {
public:
    explicit TriggerState(TriggerType type) noexcept : type_(type) {}

    /// One evaluation: did the filters match? Returns whether an event fires.
    /// After a once trigger fired, finished() is true and nothing fires again.
    bool fire(bool matched) noexcept;
    /// A once trigger that fired: the registration is to be released.
    bool finished() const noexcept { return finished_; }
    TriggerType type() const noexcept { return type_; }

private:
    TriggerType type_;
    bool was_matching_ = false;
    bool finished_ = false;
};

}  // namespace nclink::events_detail
