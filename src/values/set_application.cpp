// Running a parsed Set on a value. Every change is computed first and
// committed only when all of it succeeded, so a failed multi-key/multi-index
// set leaves the value untouched.
#include "values/value_internal.hpp"

#include <functional>
#include <map>
#include <set>
#include <utility>

namespace nclink {

using values_detail::fail;
using values_detail::patch_element;

namespace {

// Re-checks what parse_set guarantees, for requests a driver built by hand.
Result<void> check_request(const SetParams& request, DataKind kind) {
    const auto op = request.operation;
    if (kind == DataKind::single && op != SetOperation::set_value)
        return fail(ErrorCode::attribute_error, "{} needs a dict or list item", to_string(op));
    if (kind == DataKind::single && !request.whole_item())
        return fail(ErrorCode::arguments_nimiety, "a single-valued item is accessed only as a whole");
    if (kind == DataKind::dict && !request.indexes.empty())
        return fail(ErrorCode::arguments_nimiety, "a dict item takes keys, not indexes");
    if (kind == DataKind::list && !request.keys.empty())
        return fail(ErrorCode::arguments_nimiety, "a list item takes indexes, not keys");
    const bool partial = request.offset || request.length;
    if (partial && (kind != DataKind::list || op != SetOperation::set_value))
        return fail(ErrorCode::arguments_nimiety, "offset/length apply only to set_value on list elements");
    if (partial && request.whole_item()) return fail(ErrorCode::no_index, "offset/length need the index of an element");
    if (op != SetOperation::set_value && request.whole_item()) {
        if (kind == DataKind::dict) return fail(ErrorCode::no_key, "{} needs a key", to_string(op));
        return fail(ErrorCode::no_index, "{} needs an index", to_string(op));
    }
    if (op == SetOperation::remove) {
        if (!request.values.empty()) return fail(ErrorCode::arguments_nimiety, "delete takes no value");
        return ok_result();
    }
    const auto targets = request.target_count();
    const auto given = request.values.size();
    if (given == 0) return fail(ErrorCode::parameter_missing, "{} needs a value", to_string(op));
    if (given != 1 && given < targets) return fail(ErrorCode::parameter_missing, "{} values for {} targets", given, targets);
    if (given > targets) return fail(ErrorCode::arguments_nimiety, "{} values for {} target(s)", given, targets);
    return ok_result();
}

Result<void> set_whole(const SetParams& request, Json& current, DataKind kind) {
    const Json& value = request.value_for(0);
    if (kind == DataKind::dict && !value.is_object())
        return fail(ErrorCode::value_type, "a dict item's value must be an object, got {}", json_type_name(value));
    if (kind == DataKind::list && !value.is_array())
        return fail(ErrorCode::value_type, "a list item's value must be an array, got {}", json_type_name(value));
    if (kind == DataKind::single && !same_value_type(current, value))
        return fail(ErrorCode::value_type, "the item holds a {}, the new value is a {}", json_type_name(current),
                    json_type_name(value));
    current = value;
    return ok_result();
}

Result<void> set_dict(const SetParams& request, Json& current) {
    if (!current.is_object()) return fail(ErrorCode::unavailable, "the dict value is {}, not an object", json_type_name(current));
    const auto& keys = request.keys;
    switch (request.operation) {
        case SetOperation::set_value: {
            std::vector<std::pair<const std::string*, Json>> changes;
            changes.reserve(keys.size());
            for (std::size_t i = 0; i < keys.size(); ++i) {
                const auto found = current.find(keys[i]);
                if (found == current.end()) return fail(ErrorCode::key_error, "key \"{}\" is not in the dict", keys[i]);
                auto element =
                    patch_element(*found, request.value_for(i), std::nullopt, std::nullopt, fmt::format("key \"{}\"", keys[i]));
                if (!element) return std::move(element).error();
                changes.emplace_back(&keys[i], std::move(*element));
            }
            for (auto& [key, element] : changes) current[*key] = std::move(element);
            return ok_result();
        }
        case SetOperation::add: {
            std::set<std::string_view> adding;
            for (const auto& key : keys) {
                if (current.contains(key)) return fail(ErrorCode::key_error, "key \"{}\" already exists", key);
                if (!adding.insert(key).second) return fail(ErrorCode::key_error, "key \"{}\" is added twice", key);
            }
            for (std::size_t i = 0; i < keys.size(); ++i) current[keys[i]] = request.value_for(i);
            return ok_result();
        }
        case SetOperation::remove: {
            for (const auto& key : keys)
                if (!current.contains(key)) return fail(ErrorCode::key_error, "key \"{}\" is not in the dict", key);
            for (const auto& key : keys) current.erase(key);  // a repeated key is simply gone already
            return ok_result();
        }
    }
    return ok_result();
}

Result<void> set_list(const SetParams& request, Json& current) {
    if (!current.is_array()) return fail(ErrorCode::unavailable, "the list value is {}, not an array", json_type_name(current));
    const std::size_t size = current.size();
    switch (request.operation) {
        case SetOperation::set_value: {
            auto selected = expand_indexes(request.indexes, size);
            if (!selected) return std::move(selected).error();
            // A repeated index sees the result of its earlier write (two bit
            // writes to one register both take effect).
            std::map<std::size_t, Json> pending;
            for (std::size_t t = 0; t < selected->size(); ++t) {
                const std::size_t i = (*selected)[t];
                const auto earlier = pending.find(i);
                const Json& base = earlier != pending.end() ? earlier->second : current[i];
                auto element =
                    patch_element(base, request.value_for(t), request.offset, request.length, fmt::format("element {}", i));
                if (!element) return std::move(element).error();
                pending[i] = std::move(*element);
            }
            for (auto& [i, element] : pending) current[i] = std::move(element);
            return ok_result();
        }
        case SetOperation::add: {
            if (request.indexes.size() != 1 || request.indexes.front().count() != 1)
                return fail(ErrorCode::arguments_nimiety, "add inserts at one index");
            const std::size_t at = request.indexes.front().first;
            if (at > size)
                return fail(ErrorCode::out_of_range, "index {} is beyond the list length {} (add appends at {})", at, size, size);
            current.insert(current.begin() + static_cast<std::ptrdiff_t>(at), request.value_for(0));
            return ok_result();
        }
        case SetOperation::remove: {
            auto selected = expand_indexes(request.indexes, size);
            if (!selected) return std::move(selected).error();
            // Indexes name elements of the list before the delete; erase from
            // the back so earlier positions stay valid.
            const std::set<std::size_t, std::greater<>> doomed(selected->begin(), selected->end());
            for (const auto i : doomed) current.erase(i);
            return ok_result();
        }
    }
    return ok_result();
}

}  // namespace

Result<void> apply(const SetParams& request, Json& current, DataKind kind, bool setable) {
    if (!setable) return fail(ErrorCode::permission_denied, "the item is not setable");
    if (auto ok = check_request(request, kind); !ok) return std::move(ok).error();
    if (request.operation == SetOperation::set_value && request.whole_item()) return set_whole(request, current, kind);
    if (kind == DataKind::dict) return set_dict(request, current);
    return set_list(request, current);
}

Result<void> apply_set(const Json& params, Json& current, DataKind kind, bool setable) {
    // A read-only item refuses every set, however it is spelled.
    if (!setable) return fail(ErrorCode::permission_denied, "the item is not setable");
    auto request = parse_set(params, kind);
    if (!request) return std::move(request).error();
    return apply(*request, current, kind, setable);
}

}  // namespace nclink
