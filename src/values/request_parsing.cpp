// `params` of one Query/Set item -> QueryParams / SetParams, validated
// against the item's DataKind. Liberal in spelling (value/values, key/keys,
// index/indexes, numeric strings, omitted operation), strict in meaning.
#include "values/value_internal.hpp"

#include <algorithm>
#include <array>
#include <cctype>

namespace nclink {

using values_detail::fail;

namespace {

// The parameters one item's `params` may hold. Null counts as absent for all
// of them except `value`, where null is a value to write.
struct RawParams {
    const Json* operation = nullptr;
    const Json* key = nullptr;
    const Json* keys = nullptr;
    const Json* index = nullptr;
    const Json* indexes = nullptr;
    const Json* value = nullptr;
    const Json* values = nullptr;
    const Json* offset = nullptr;
    const Json* length = nullptr;

    bool has_keys() const { return key || keys; }
    bool has_indexes() const { return index || indexes; }
};

Result<RawParams> scan(const Json& params, bool for_set) {
    if (!params.is_object()) return fail(ErrorCode::syntax_error, "params must be a JSON object, got {}", json_type_name(params));
    RawParams raw;
    for (const auto& [name, item] : params.items()) {
        const Json* const present = (item.is_null() && name != "value") ? nullptr : &item;
        if (name == "operation") raw.operation = present;
        else if (name == "key") raw.key = present;
        else if (name == "keys") raw.keys = present;
        else if (name == "index") raw.index = present;
        else if (name == "indexes") raw.indexes = present;
        else if (for_set && name == "value") raw.value = present;
        else if (for_set && name == "values") raw.values = present;
        else if (name == "offset") raw.offset = present;  // Set, and appendix A's Query_Params
        else if (name == "length") raw.length = present;
        else return fail(ErrorCode::keys_of_arguments, "unknown parameter \"{}\" in {} params", name, for_set ? "Set" : "Query");
    }
    return raw;
}

std::string lower(const std::string& text) {
    std::string out = text;
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

Result<std::string> operation_name(const Json& operation) {
    if (!operation.is_string())
        return fail(ErrorCode::value_type, "operation must be a string, got {}", json_type_name(operation));
    return lower(operation.get_ref<const std::string&>());
}

// `key` / `keys`: a string or an array of strings.
Result<std::vector<std::string>> parse_keys(const RawParams& raw) {
    if (raw.key && raw.keys) return fail(ErrorCode::arguments_nimiety, "both key and keys given");
    const Json& given = raw.key ? *raw.key : *raw.keys;
    std::vector<std::string> keys;
    if (given.is_string()) {
        keys.push_back(given.get<std::string>());
    } else if (given.is_array()) {
        for (const auto& key : given) {
            if (!key.is_string()) return fail(ErrorCode::value_type, "keys must be strings, got {}", json_type_name(key));
            keys.push_back(key.get<std::string>());
        }
    } else {
        return fail(ErrorCode::value_type, "key must be a string or an array of strings, got {}", json_type_name(given));
    }
    if (keys.empty()) return fail(ErrorCode::no_key, "the keys array is empty");
    return keys;
}

// `index` / `indexes`: one entry or an array of entries (numbers, numeric
// strings, ranges). Example 8.2.14-3 echoes `"index": ["0"]`, so `index`
// takes an array too.
Result<std::vector<IndexRange>> parse_indexes(const RawParams& raw) {
    if (raw.index && raw.indexes) return fail(ErrorCode::arguments_nimiety, "both index and indexes given");
    const Json& given = raw.index ? *raw.index : *raw.indexes;
    std::vector<IndexRange> ranges;
    if (given.is_array()) {
        for (const auto& entry : given) {
            auto range = parse_index(entry);
            if (!range) return std::move(range).error();
            ranges.push_back(*range);
        }
        if (ranges.empty()) return fail(ErrorCode::no_index, "the indexes array is empty");
    } else {
        auto range = parse_index(given);
        if (!range) return std::move(range).error();
        ranges.push_back(*range);
    }
    return ranges;
}

Result<void> parse_selectors(const RawParams& raw, std::vector<std::string>& keys, std::vector<IndexRange>& indexes) {
    if (raw.has_keys()) {
        auto parsed = parse_keys(raw);
        if (!parsed) return std::move(parsed).error();
        keys = std::move(*parsed);
    }
    if (raw.has_indexes()) {
        auto parsed = parse_indexes(raw);
        if (!parsed) return std::move(parsed).error();
        indexes = std::move(*parsed);
    }
    return ok_result();
}

// Selectors the item's kind cannot take: 409 (they are valid parameter names,
// just more than this item needs).
Result<void> check_selector_kind(const RawParams& raw, DataKind kind) {
    if (kind == DataKind::single && (raw.has_keys() || raw.has_indexes()))
        return fail(ErrorCode::arguments_nimiety, "a single-valued item is accessed only as a whole (no key/index)");
    if (kind == DataKind::dict && raw.has_indexes())
        return fail(ErrorCode::arguments_nimiety, "a dict item takes keys, not indexes");
    if (kind == DataKind::list && raw.has_keys())
        return fail(ErrorCode::arguments_nimiety, "a list item takes indexes, not keys");
    return ok_result();
}

}  // namespace

std::string_view to_string(QueryOperation op) noexcept {
    switch (op) {
        case QueryOperation::get_value: return "get_value";
        case QueryOperation::get_keys: return "get_keys";
        case QueryOperation::get_length: return "get_length";
        case QueryOperation::get_attributes: return "get_attributes";
    }
    return "get_value";
}

std::string_view to_string(SetOperation op) noexcept {
    switch (op) {
        case SetOperation::set_value: return "set_value";
        case SetOperation::add: return "add";
        case SetOperation::remove: return "delete";
    }
    return "set_value";
}

std::size_t SetParams::target_count() const noexcept {
    if (!keys.empty()) return keys.size();
    if (!indexes.empty()) return index_count(indexes);
    return 1;
}

const Json& SetParams::value_for(std::size_t target) const noexcept {
    static const Json none;
    if (values.size() == 1) return values.front();
    return target < values.size() ? values[target] : none;
}

Result<QueryParams> parse_query(const Json& params, DataKind kind) {
    QueryParams request;
    if (params.is_null()) return request;
    auto scanned = scan(params, false);
    if (!scanned) return std::move(scanned).error();
    const RawParams& raw = *scanned;

    if (raw.operation) {
        auto name = operation_name(*raw.operation);
        if (!name) return std::move(name).error();
        if (*name == "get_value" || *name == "get_values") request.operation = QueryOperation::get_value;
        else if (*name == "get_keys") request.operation = QueryOperation::get_keys;
        else if (*name == "get_length") request.operation = QueryOperation::get_length;
        // "get_attribute": appendix A's Query_Params spelling; 8.2.11 writes get_attributes.
        else if (*name == "get_attributes" || *name == "get_attribute") request.operation = QueryOperation::get_attributes;
        else return fail(ErrorCode::keys_of_arguments, "unknown Query operation \"{}\"", *name);
    }
    switch (request.operation) {
        case QueryOperation::get_keys:
            if (kind != DataKind::dict)
                return fail(ErrorCode::unsupported_get_keys, "get_keys needs a dict item, this one is {}", to_string(kind));
            break;
        case QueryOperation::get_length:
            if (kind != DataKind::list)
                return fail(ErrorCode::unsupported_get_length, "get_length needs a list item, this one is {}", to_string(kind));
            break;
        case QueryOperation::get_attributes:
            if (kind == DataKind::single)
                return fail(ErrorCode::unsupported_get_attributes,
                            "get_attributes needs a dict or list item, this one is single");
            break;
        case QueryOperation::get_value: break;
    }
    if (auto ok = check_selector_kind(raw, kind); !ok) return std::move(ok).error();
    const bool takes_selectors =
        request.operation == QueryOperation::get_value || request.operation == QueryOperation::get_attributes;
    if (!takes_selectors && (raw.has_keys() || raw.has_indexes()))
        return fail(ErrorCode::arguments_nimiety, "{} takes no key/index", to_string(request.operation));
    if (auto ok = parse_selectors(raw, request.keys, request.indexes); !ok) return std::move(ok).error();

    // get_value without a selector is the whole item; get_attributes needs one.
    if (request.operation == QueryOperation::get_attributes && request.keys.empty() && request.indexes.empty()) {
        if (kind == DataKind::dict) return fail(ErrorCode::no_key, "get_attributes needs keys");
        return fail(ErrorCode::no_index, "get_attributes needs indexes");
    }
    // Appendix A Query_Params offset/length: a part of list elements, read
    // as a Set writes it (8.2.13 example 3).
    if (raw.offset || raw.length) {
        if (kind != DataKind::list) return fail(ErrorCode::arguments_nimiety, "offset/length apply only to list elements");
        if (request.operation != QueryOperation::get_value)
            return fail(ErrorCode::arguments_nimiety, "{} takes no offset/length", to_string(request.operation));
        if (request.indexes.empty()) return fail(ErrorCode::no_index, "offset/length need the index of an element");
        if (raw.offset) {
            auto offset = values_detail::parse_count(*raw.offset, "offset");
            if (!offset) return std::move(offset).error();
            request.offset = *offset;
        }
        if (raw.length) {
            auto length = values_detail::parse_count(*raw.length, "length");
            if (!length) return std::move(length).error();
            request.length = *length;
        }
    }
    return request;
}

Result<SetParams> parse_set(const Json& params, DataKind kind) {
    SetParams request;
    if (params.is_null()) return fail(ErrorCode::parameter_missing, "Set params are missing: no value to write");
    auto scanned = scan(params, true);
    if (!scanned) return std::move(scanned).error();
    const RawParams& raw = *scanned;

    if (raw.operation) {
        auto name = operation_name(*raw.operation);
        if (!name) return std::move(name).error();
        // "set_values" is how example 8.2.14-2 spells it.
        if (*name == "set_value" || *name == "set_values") request.operation = SetOperation::set_value;
        else if (*name == "add") request.operation = SetOperation::add;
        else if (*name == "delete") request.operation = SetOperation::remove;
        else return fail(ErrorCode::keys_of_arguments, "unknown Set operation \"{}\"", *name);
    }
    const auto op = request.operation;
    if (kind == DataKind::single && op != SetOperation::set_value)
        return fail(ErrorCode::attribute_error, "{} needs a dict or list item, this one is single", to_string(op));

    if (auto ok = check_selector_kind(raw, kind); !ok) return std::move(ok).error();
    const bool partial = raw.offset || raw.length;
    if (partial && kind != DataKind::list) return fail(ErrorCode::arguments_nimiety, "offset/length apply only to list elements");
    if (partial && op != SetOperation::set_value)
        return fail(ErrorCode::arguments_nimiety, "{} takes no offset/length", to_string(op));
    if (raw.value && raw.values) return fail(ErrorCode::arguments_nimiety, "both value and values given");
    const bool has_value = raw.value || raw.values;
    if (op == SetOperation::remove && has_value) return fail(ErrorCode::arguments_nimiety, "delete takes no value");

    if (auto ok = parse_selectors(raw, request.keys, request.indexes); !ok) return std::move(ok).error();

    const bool selected = !request.keys.empty() || !request.indexes.empty();
    if (op != SetOperation::set_value && !selected) {
        if (kind == DataKind::dict) return fail(ErrorCode::no_key, "{} needs a key", to_string(op));
        return fail(ErrorCode::no_index, "{} needs an index", to_string(op));
    }
    if (partial && !selected) return fail(ErrorCode::no_index, "offset/length need the index of an element");
    if (op == SetOperation::add && kind == DataKind::list && index_count(request.indexes) != 1)
        return fail(ErrorCode::arguments_nimiety, "add inserts at one index");

    if (raw.offset) {
        auto offset = values_detail::parse_count(*raw.offset, "offset");
        if (!offset) return std::move(offset).error();
        request.offset = *offset;
    }
    if (raw.length) {
        auto length = values_detail::parse_count(*raw.length, "length");
        if (!length) return std::move(length).error();
        request.length = *length;
    }

    if (op == SetOperation::remove) return request;
    if (!has_value) return fail(ErrorCode::parameter_missing, "{} needs a value", to_string(op));
    if (raw.value) {
        request.values.push_back(*raw.value);
    } else if (raw.values->is_array()) {
        request.values = raw.values->get<std::vector<Json>>();
    } else {
        request.values.push_back(*raw.values);  // `values: 12.5` means `value: 12.5`
    }
    // One value per target, or one value for all targets.
    const std::size_t targets = request.target_count();
    const std::size_t given = request.values.size();
    if (given == 0) return fail(ErrorCode::parameter_missing, "the values array is empty");
    if (given != 1 && given < targets) return fail(ErrorCode::parameter_missing, "{} values for {} targets", given, targets);
    if (given > targets) return fail(ErrorCode::arguments_nimiety, "{} values for {} target(s)", given, targets);
    return request;
}

}  // namespace nclink
