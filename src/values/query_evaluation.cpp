// Running a parsed Query on a value: the response `values` array.
#include "values/value_internal.hpp"

namespace nclink {

using values_detail::fail;

namespace {

// Element access needs the value in its kind's shape; null (not known yet)
// or a wrongly shaped value is "Unavailable", not a request error.
Result<void> check_shape(const Json& current, DataKind kind) {
    if (kind == DataKind::dict && !current.is_object())
        return fail(ErrorCode::unavailable, "the dict value is {}, not an object", json_type_name(current));
    if (kind == DataKind::list && !current.is_array())
        return fail(ErrorCode::unavailable, "the list value is {}, not an array", json_type_name(current));
    return ok_result();
}

Json element_answer(const Json& element, QueryOperation op) {
    if (op == QueryOperation::get_attributes) return Json(std::string(json_type_name(element)));
    return element;
}

// `[value]`, built without an initializer list (which copies through a
// proxy and checks whether the list looks like an object).
Json whole(Json value) {
    Json out(Json::value_t::array);
    out.get_ref<Json::array_t&>().push_back(std::move(value));
    return out;
}

}  // namespace

Result<Json> evaluate(const QueryParams& request, Json&& current, DataKind kind) {
    if (request.whole_item()) return whole(std::move(current));
    return evaluate(request, static_cast<const Json&>(current), kind);
}

Result<Json> evaluate(const QueryParams& request, const Json& current, DataKind kind) {
    if (request.whole_item()) return whole(current);
    if (auto shape = check_shape(current, kind); !shape) return std::move(shape).error();

    Json out = Json::array();
    switch (request.operation) {
        case QueryOperation::get_keys:
            if (kind != DataKind::dict) return fail(ErrorCode::unsupported_get_keys, "get_keys needs a dict item");
            for (const auto& entry : current.items()) out.push_back(entry.key());
            return out;
        case QueryOperation::get_length:
            if (kind != DataKind::list) return fail(ErrorCode::unsupported_get_length, "get_length needs a list item");
            out.push_back(current.size());
            return out;
        case QueryOperation::get_value:
        case QueryOperation::get_attributes: break;
    }
    if (kind == DataKind::single) return fail(ErrorCode::arguments_nimiety, "a single-valued item is accessed only as a whole");
    if (kind == DataKind::dict) {
        if (!request.indexes.empty()) return fail(ErrorCode::arguments_nimiety, "a dict item takes keys");
        if (request.keys.empty()) return fail(ErrorCode::no_key, "{} needs keys", to_string(request.operation));
        for (const auto& key : request.keys) {
            const auto found = current.find(key);
            if (found == current.end()) return fail(ErrorCode::key_error, "key \"{}\" is not in the dict", key);
            out.push_back(element_answer(*found, request.operation));
        }
        return out;
    }
    if (!request.keys.empty()) return fail(ErrorCode::arguments_nimiety, "a list item takes indexes");
    if (request.indexes.empty()) return fail(ErrorCode::no_index, "{} needs indexes", to_string(request.operation));
    auto selected = expand_indexes(request.indexes, current.size());
    if (!selected) return std::move(selected).error();
    const bool part = request.offset || request.length;
    for (const auto i : *selected) {
        if (!part) {
            out.push_back(element_answer(current[i], request.operation));
            continue;
        }
        auto piece = values_detail::element_part(current[i], request.offset, request.length, fmt::format("element {}", i));
        if (!piece) return std::move(piece).error();
        out.push_back(std::move(piece).value());
    }
    return out;
}

Result<Json> evaluate_query(const Json& params, const Json& current, DataKind kind) {
    auto request = parse_query(params, kind);
    if (!request) return std::move(request).error();
    return evaluate(*request, current, kind);
}

}  // namespace nclink
