#include "events/event_filter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

namespace nclink::events_detail {
namespace {

Error mismatch(std::string message) { return make_error(ErrorCode::filter_arguments_mismatch, std::move(message)); }

bool is_scalar_argument(const Json& v) { return v.is_number() || v.is_string() || v.is_boolean(); }

// The keys each type takes besides "type" (figure 16).
std::vector<std::string_view> allowed_keys(FilterType type) {
    switch (type) {
        case FilterType::change: return {"variance"};
        case FilterType::equal: return {"value"};
        case FilterType::range: return {"from", "to", "variance"};
        case FilterType::less:
        case FilterType::greater: return {"value", "variance"};
        case FilterType::include: return {"values"};
    }
    return {};
}

Result<double> number_argument(const Json& filter, const char* key, FilterType type) {
    const auto it = filter.find(key);
    if (it == filter.end()) return mismatch(fmt::format("a {} filter needs \"{}\"", to_string(type), key));
    if (!it->is_number()) return mismatch(fmt::format("\"{}\" of a {} filter must be a number", key, to_string(type)));
    const double value = it->get<double>();
    if (!std::isfinite(value)) return mismatch(fmt::format("\"{}\" must be finite", key));
    return value;
}

}  // namespace

std::string_view to_string(FilterType type) noexcept {
    switch (type) {
        case FilterType::change: return "change";
        case FilterType::equal: return "equal";
        case FilterType::range: return "range";
        case FilterType::less: return "less";
        case FilterType::greater: return "greater";
        case FilterType::include: return "include";
    }
    return "change";
}

std::optional<FilterType> filter_type_from_string(std::string_view name) noexcept {
    std::string lower(name);
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (auto type :
         {FilterType::change, FilterType::equal, FilterType::range, FilterType::less, FilterType::greater, FilterType::include})
        if (lower == to_string(type)) return type;
    return std::nullopt;
}

Result<EventFilter> parse_filter(const Json& filter) {
    if (!filter.is_object()) return make_error(ErrorCode::filter_type, "a filter must be a JSON object");
    const auto type_it = filter.find("type");
    if (type_it == filter.end()) return make_error(ErrorCode::filter_type, "a filter without \"type\"");
    if (!type_it->is_string()) return make_error(ErrorCode::filter_type, "the filter \"type\" must be a string");
    const auto type = filter_type_from_string(type_it->get_ref<const std::string&>());
    if (!type)
        return make_error(ErrorCode::filter_type,
                          fmt::format("unknown filter type \"{}\" (change, equal, range, less, greater, include)",
                                      type_it->get_ref<const std::string&>()));

    const auto allowed = allowed_keys(*type);
    for (const auto& entry : filter.items()) {
        if (entry.key() == "type") continue;
        if (std::find(allowed.begin(), allowed.end(), entry.key()) == allowed.end())
            return mismatch(fmt::format("a {} filter takes no \"{}\"", to_string(*type), entry.key()));
    }

    EventFilter out;
    out.type = *type;
    switch (*type) {
        case FilterType::change: break;
        case FilterType::equal: {
            const auto it = filter.find("value");
            if (it == filter.end()) return mismatch("an equal filter needs \"value\"");
            if (!is_scalar_argument(*it)) return mismatch("\"value\" of an equal filter must be a number, string or boolean");
            out.value = *it;
            break;
        }
        case FilterType::range: {
            auto from = number_argument(filter, "from", *type);
            if (!from) return std::move(from).error();
            auto to = number_argument(filter, "to", *type);
            if (!to) return std::move(to).error();
            out.from = *from;
            out.to = *to;
            break;
        }
        case FilterType::less:
        case FilterType::greater: {
            auto value = number_argument(filter, "value", *type);
            if (!value) return std::move(value).error();
            out.value = filter.at("value");
            break;
        }
        case FilterType::include: {
            const auto it = filter.find("values");
            if (it == filter.end()) return mismatch("an include filter needs \"values\"");
            if (!it->is_array()) return mismatch("\"values\" of an include filter must be an array");
            for (const auto& v : *it) {
                if (!is_scalar_argument(v)) return mismatch("every entry of \"values\" must be a number, string or boolean");
                out.values.push_back(v);
            }
            break;
        }
    }
    if (filter.contains("variance")) {
        auto variance = number_argument(filter, "variance", *type);
        if (!variance) return std::move(variance).error();
        if (*variance < 0) return mismatch("\"variance\" must not be negative");
        out.variance = *variance;
    }
    return out;
}

Result<std::vector<EventFilter>> parse_filters(const std::optional<std::vector<Json>>& filters) {
    std::vector<EventFilter> out;
    if (filters) {
        for (const auto& filter : *filters) {
            auto parsed = parse_filter(filter);
            if (!parsed) return std::move(parsed).error();
            out.push_back(std::move(parsed).value());
        }
    }
    if (out.empty()) out.push_back(EventFilter{});  // 8.2.27.4: no filter means change
    return out;
}

bool same_value(const Json& a, const Json& b) {
    if (a.is_number() && b.is_number()) {
        if (a.is_number_float() || b.is_number_float()) return a.get<double>() == b.get<double>();
        return a == b;  // integers: exact, also beyond 2^53
    }
    return a == b;
}

bool condition_holds(const EventFilter& filter, const Json& value, const Json* previous) {
    switch (filter.type) {
        case FilterType::change: return previous != nullptr && !same_value(*previous, value);
        case FilterType::equal: return same_value(filter.value, value);
        case FilterType::range: return value.is_number() && value.get<double>() > filter.from && value.get<double>() < filter.to;
        case FilterType::less: return value.is_number() && value.get<double>() < filter.value.get<double>();
        case FilterType::greater: return value.is_number() && value.get<double>() > filter.value.get<double>();
        case FilterType::include:
            return std::any_of(filter.values.begin(), filter.values.end(), [&](const Json& v) { return same_value(v, value); });
    }
    return false;
}

bool variance_holds(const EventFilter& filter, const Json& value, const Json* recorded) {
    if (!filter.variance || recorded == nullptr) return true;
    if (!value.is_number() || !recorded->is_number()) return true;
    return std::fabs(value.get<double>() - recorded->get<double>()) >= *filter.variance;
}

bool filter_matches(const EventFilter& filter, const Json& value, const Json* previous, const Json* recorded) {
    return condition_holds(filter, value, previous) && variance_holds(filter, value, recorded);
}

std::optional<std::size_t> first_match(const std::vector<EventFilter>& filters, const Json& value, const Json* previous,
                                       const Json* recorded) {
    for (std::size_t i = 0; i < filters.size(); ++i)
        if (filter_matches(filters[i], value, previous, recorded)) return i;
    return std::nullopt;
}

}  // namespace nclink::events_detail
