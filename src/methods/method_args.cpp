#include "methods/method_args.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <map>
#include <string>
#include <vector>

namespace nclink::methods_detail {
namespace {

struct Param {
    bool required = true;
    std::optional<Json> fallback;  ///< "default" of an array entry
};

/// name -> parameter; std::nullopt when the model declares nothing.
std::optional<std::map<std::string, Param>> declared(const Json& args) {
    if (args.is_object()) {
        std::map<std::string, Param> out;
        for (auto it = args.begin(); it != args.end(); ++it) out.emplace(it.key(), Param{});
        return out;
    }
    if (args.is_array()) {
        std::map<std::string, Param> out;
        for (const Json& entry : args) {
            if (entry.is_string()) {
                out.emplace(entry.get<std::string>(), Param{});
                continue;
            }
            if (!entry.is_object()) continue;  // not a parameter description
            std::string name;
            for (const char* key : {"name", "id"}) {
                auto it = entry.find(key);
                if (it != entry.end() && it->is_string()) {
                    name = it->get<std::string>();
                    break;
                }
            }
            if (name.empty()) continue;
            Param p;
            if (auto d = entry.find("default"); d != entry.end()) {
                p.required = false;
                p.fallback = *d;
            }
            if (auto o = entry.find("optional"); o != entry.end() && o->is_boolean() && o->get<bool>()) p.required = false;
            out.emplace(std::move(name), std::move(p));
        }
        return out;
    }
    return std::nullopt;
}

}  // namespace

Result<Json> check_method_args(const Method& method, const std::optional<Json>& call_args) {
    Json args = call_args && !call_args->is_null() ? *call_args : Json::object();
    if (!args.is_object())
        return make_error(ErrorCode::value_type,
                          fmt::format("args of method {} must be an object, not {}", method.id, args.type_name()));
    const auto params = declared(method.args);
    if (!params) return args;
    std::vector<std::string> missing, unknown;
    for (const auto& [name, param] : *params) {
        if (args.contains(name)) continue;
        if (param.fallback) args[name] = *param.fallback;
        else if (param.required) missing.push_back(name);
    }
    for (auto it = args.begin(); it != args.end(); ++it)
        if (!params->count(it.key())) unknown.push_back(it.key());
    if (!missing.empty())
        return make_error(ErrorCode::parameter_missing,
                          fmt::format("method {} needs args {}", method.id, fmt::join(missing, ", ")));
    if (!unknown.empty())
        return make_error(ErrorCode::arguments_nimiety,
                          fmt::format("method {} takes no args {}", method.id, fmt::join(unknown, ", ")));
    return args;
}

}  // namespace nclink::methods_detail
