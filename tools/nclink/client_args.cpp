#include "client_args.hpp"

#include <fmt/format.h>

namespace nclink {
namespace {

Result<Json> parse_params(std::string_view text) {
    Json params = Json::parse(text.begin(), text.end(), nullptr, false);
    if (params.is_discarded() || !params.is_object())
        return make_error(ErrorCode::syntax_error, fmt::format("params are not a JSON object: {}", text));
    return params;
}

std::string status_text(const ResponseStatus& status) {
    std::string out = "NG";
    if (status.error) out += " " + std::to_string(*status.error);
    if (status.reason) out += " " + *status.reason;
    return out;
}

std::string dump(const Json& value) { return value.dump(-1, ' ', false, Json::error_handler_t::replace); }

}  // namespace

Result<QueryItem> parse_query_spec(std::string_view spec) {
    const auto colon = spec.find(':');
    QueryItem item;
    item.id = std::string(spec.substr(0, colon));
    if (item.id.empty()) return make_error(ErrorCode::parameter_missing, fmt::format("no id in \"{}\"", spec));
    if (colon != std::string_view::npos) {
        auto params = parse_params(spec.substr(colon + 1));
        if (!params) return std::move(params).error();
        item.params = std::move(params).value();
    }
    return item;
}

Result<SetItem> parse_set_spec(std::string_view spec) {
    const auto split = spec.find_first_of("=:");
    if (split == std::string_view::npos)
        return make_error(ErrorCode::parameter_missing, fmt::format("\"{}\" is neither ID=VALUE nor ID:{{params}}", spec));
    SetItem item;
    item.id = std::string(spec.substr(0, split));
    if (item.id.empty()) return make_error(ErrorCode::parameter_missing, fmt::format("no id in \"{}\"", spec));
    const std::string_view rest = spec.substr(split + 1);
    if (spec[split] == '=') {
        item.params = Json{{"value", parse_value_text(rest)}};
    } else {
        auto params = parse_params(rest);
        if (!params) return std::move(params).error();
        item.params = std::move(params).value();
    }
    return item;
}

Json parse_value_text(std::string_view text) {
    Json value = Json::parse(text.begin(), text.end(), nullptr, false);
    if (value.is_discarded()) return Json(std::string(text));
    return value;
}

std::string format_values(const Json& values) {
    if (values.is_array() && values.size() == 1) return dump(values.front());
    return dump(values);
}

std::string format_query_result(const QueryResult& result) {
    if (!result.status.ok) return result.id + ": " + status_text(result.status);
    return result.id + " = " + (result.values ? format_values(*result.values) : std::string("(no values)"));
}

std::string format_set_result(const SetResult& result) {
    return result.id + ": " + (result.status.ok ? std::string("OK") : status_text(result.status));
}

}  // namespace nclink
