// Reads typed keys of one JSON configuration object and remembers which were
// seen, so unknown keys (typos) are reported instead of passing silently.
// Shared by every configuration section (adapter, sampling, events, methods,
// agent); each section reads its own keys with one reader.
#pragma once

#include "core/nearest.hpp"

#include <nclink/error.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <fmt/format.h>

#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::detail {


// Reads typed keys from one JSON object and remembers which were seen, so
// unknown keys (typos) can be reported.
class ConfigReader {
public:
    ConfigReader(const Json& object, std::string where) : object_(object), where_(std::move(where)) {}

    template <class T, class Check>
    Result<void> read(const char* key, T& out, Check check, const char* type_name) {
        seen_.insert(key);
        auto it = object_.find(key);
        if (it == object_.end() || it->is_null()) return ok_result();
        if (!check(*it))
            return make_error(ErrorCode::value_type, fmt::format("configuration: {}{} must be {}", where_, key, type_name));
        out = it->template get<T>();
        return ok_result();
    }
    Result<void> str(const char* key, std::string& out) {
        return read(key, out, [](const Json& j) { return j.is_string(); }, "a string");
    }
    Result<void> boolean(const char* key, bool& out) {
        return read(key, out, [](const Json& j) { return j.is_boolean(); }, "true or false");
    }
    template <class T>
    Result<void> count(const char* key, T& out) {
        return read(key, out, [](const Json& j) { return j.is_number_unsigned() || (j.is_number_integer() && j.get<long long>() >= 0); },
                    "a non-negative integer");
    }
    template <class Duration>
    Result<void> duration(const char* key, Duration& out) {
        long long value = 0;
        bool given = object_.contains(key) && !object_[key].is_null();
        if (auto r = count(key, value); !r) return r;
        if (given) out = Duration(value);
        return ok_result();
    }
    const Json* object(const char* key) {
        seen_.insert(key);
        auto it = object_.find(key);
        return it == object_.end() || it->is_null() ? nullptr : &*it;
    }
    Result<void> no_unknown_keys() const {
        for (auto it = object_.begin(); it != object_.end(); ++it) {
            if (seen_.count(it.key())) continue;
            // A typo ("broker.uri") names the key it most likely meant.
            const std::vector<std::string_view> known(seen_.begin(), seen_.end());
            const auto hint = nearest_name(it.key(), known);
            return make_error(ErrorCode::keys_of_arguments,
                              fmt::format("configuration: unknown key {}{}{}", where_, it.key(),
                                          hint ? fmt::format(" (did you mean {}{}?)", where_, *hint) : std::string()));
        }
        return ok_result();
    }

private:
    const Json& object_;
    std::string where_;
    std::set<std::string> seen_;
};

#define NCLINK_TRY(expr)                   \
    do {                                   \
        if (auto r_ = (expr); !r_) return std::move(r_).error(); \
    } while (0)


}  // namespace nclink::detail
