#include "events/event_registration.hpp"

#include <fmt/format.h>

namespace nclink::events_detail {

Result<EventSpec> validate_registration(const EventRegisterRequest& request, const DataObject* item) {
    if (!item) return make_error(ErrorCode::node_not_exists, fmt::format("no data item '{}' on this device", request.id));
    EventSpec spec;
    spec.item = request.id;
    spec.kind = item->kind;

    // "An event watches one single-valued element" (table 48, key/index).
    if (request.key && request.index)
        return make_error(ErrorCode::arguments_nimiety, "give key or index, not both: an event watches one element");
    switch (item->kind) {
        case DataKind::dict:
            if (request.index)
                return make_error(ErrorCode::arguments_nimiety,
                                  fmt::format("{} is a dict: it takes a key, not an index", request.id));
            if (!request.key)
                return make_error(ErrorCode::no_key, fmt::format("{} is a dict: say which key to watch", request.id));
            spec.key = request.key;
            break;
        case DataKind::list:
            if (request.key)
                return make_error(ErrorCode::arguments_nimiety,
                                  fmt::format("{} is a list: it takes an index, not a key", request.id));
            if (!request.index)
                return make_error(ErrorCode::no_index, fmt::format("{} is a list: say which index to watch", request.id));
            if (*request.index < 0)
                return make_error(ErrorCode::out_of_range, fmt::format("index {} is negative", *request.index));
            spec.index = static_cast<std::size_t>(*request.index);
            break;
        case DataKind::single:
            if (request.key || request.index)
                return make_error(ErrorCode::arguments_nimiety,
                                  fmt::format("{} is a single value: it takes no key or index", request.id));
            break;
    }

    auto filters = parse_filters(request.filters);
    if (!filters) return std::move(filters).error();
    spec.filters = std::move(filters).value();
    auto trigger = parse_trigger(request.trigger_type);
    if (!trigger) return std::move(trigger).error();
    spec.trigger = *trigger;
    return spec;
}

Result<Json> extract_element(const EventSpec& spec, const Json& whole) {
    if (spec.key) {
        if (!whole.is_object()) return make_error(ErrorCode::unavailable, fmt::format("{} is not a dict value now", spec.item));
        const auto it = whole.find(*spec.key);
        if (it == whole.end())
            return make_error(ErrorCode::key_error, fmt::format("key \"{}\" is not in {}", *spec.key, spec.item));
        return *it;
    }
    if (spec.index) {
        if (!whole.is_array()) return make_error(ErrorCode::unavailable, fmt::format("{} is not a list value now", spec.item));
        if (*spec.index >= whole.size())
            return make_error(ErrorCode::out_of_range,
                              fmt::format("index {} is past the end of {} ({} elements)", *spec.index, spec.item, whole.size()));
        return whole[*spec.index];
    }
    return whole;
}

}  // namespace nclink::events_detail
