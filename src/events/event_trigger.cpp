#include "events/event_trigger.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <string>

namespace nclink::events_detail {

std::string_view to_string(TriggerType type) noexcept {
    switch (type) {
        case TriggerType::always: return "always";
        case TriggerType::normal: return "normal";
        case TriggerType::once: return "once";
    }
    return "always";
}

std::optional<TriggerType> trigger_type_from_string(std::string_view name) noexcept {
    std::string lower(name);
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (auto type : {TriggerType::always, TriggerType::normal, TriggerType::once})
        if (lower == to_string(type)) return type;
    return std::nullopt;
}

Result<TriggerType> parse_trigger(std::string_view name) {
    if (auto type = trigger_type_from_string(name)) return *type;
    return make_error(ErrorCode::trigger_type, fmt::format("unknown triggerType \"{}\" (always, normal, once)", name));
}

bool TriggerState::fire(bool matched) noexcept {
    if (finished_) return false;
    bool fires = false;
    switch (type_) {
        case TriggerType::always: fires = matched; break;
        case TriggerType::normal: fires = matched && !was_matching_; break;
        case TriggerType::once:
            fires = matched;
            finished_ = matched;
            break;
    }
    was_matching_ = matched;
    return fires;
}

}  // namespace nclink::events_detail
