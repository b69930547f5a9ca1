// Reads typed keys of one JSON configuration object and remembers which were
// seen, so unknown keys (typos) are reported -- with the nearest valid key as
// a suggestion -- instead of passing silently. Shared by every configuration
// section (adapter, sampling, events, methods, agent, and any later one);
// each section reads its own keys with one reader. Every error names the key
// by its dotted path in the message and by its JSON pointer in
// Error::pointer, so tools can show the line and column in the file
// (docs/configuration.md).
#pragma once

#include <nclink/error.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <fmt/format.h>

#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace nclink::core_detail {

/// The candidate closest to `word` (edit distance with transpositions,
/// ignoring case, '_' and '-'), if it is close enough to be a likely typo.
std::optional<std::string> nearest_key(std::string_view word, const std::vector<std::string>& candidates);

/// "/a/b" + "c" -> "/a/b/c", escaping '~' and '/' (RFC 6901).
std::string pointer_append(std::string pointer, std::string_view key);

/// "broker." -> "/broker": the pointer of a section named by its dotted
/// message prefix (for sections whose keys hold no dots).
std::string pointer_of_where(std::string_view where);

class ConfigReader {
public:
    /// `where` prefixes every key in messages ("broker."); `pointer` is the
    /// section's JSON pointer ("/broker"), derived from `where` when omitted.
    ConfigReader(const Json& object, std::string where, std::optional<std::string> pointer = std::nullopt)
        : object_(object), where_(std::move(where)), pointer_(pointer ? std::move(*pointer) : pointer_of_where(where_)) {}

    template <class T, class Check>
    Result<void> read(const char* key, T& out, Check check, const char* type_name) {
        mark(key);
        auto it = object_.find(key);
        if (it == object_.end() || it->is_null()) return ok_result();
        if (!check(*it)) return fail(ErrorCode::value_type, key, std::string("must be ") + type_name);
        out = it->template get<T>();
        return ok_result();
    }
    Result<void> str(const char* key, std::string& out) {
        return read(
            key, out, [](const Json& j) { return j.is_string(); }, "a string");
    }
    Result<void> boolean(const char* key, bool& out) {
        return read(
            key, out, [](const Json& j) { return j.is_boolean(); }, "true or false");
    }
    /// A non-negative integer that fits `T`. A value past T's range is
    /// refused, never cut: a byte limit of 5 GB read into a 32-bit size_t
    /// (armhf) would otherwise become 705 MB.
    template <class T>
    Result<void> count(const char* key, T& out) {
        static_assert(std::is_integral_v<T>, "count() reads integers");
        constexpr auto max = static_cast<unsigned long long>(std::numeric_limits<T>::max());
        const auto it = object_.find(key);
        if (it != object_.end() && it->is_number_integer() && (it->is_number_unsigned() || it->template get<long long>() >= 0) &&
            it->template get<unsigned long long>() > max) {
            mark(key);
            return fail(ErrorCode::value_type, key, fmt::format("must be at most {}", max));
        }
        return read(
            key, out, [](const Json& j) { return j.is_number_unsigned() || (j.is_number_integer() && j.get<long long>() >= 0); },
            "a non-negative integer");
    }
    template <class Duration>
    Result<void> duration(const char* key, Duration& out) {
        long long value = 0;
        const auto it = object_.find(key);
        const bool given = it != object_.end() && !it->is_null();
        if (auto r = count(key, value); !r) return r;
        if (given) out = Duration(value);
        return ok_result();
    }
    /// A member read as a whole (a section or free-form value); nullptr when absent or null.
    const Json* object(const char* key) {
        mark(key);
        auto it = object_.find(key);
        return it == object_.end() || it->is_null() ? nullptr : &*it;
    }
    /// An error about `key` of this section: "configuration: <where><key>: <text>"
    /// (or "<where><key> <text>" when `text` starts with "must"), pointing at it.
    Error fail(ErrorCode code, std::string_view key, std::string_view text) const;
    /// The section's own dotted path and pointer, for errors about a member of a member.
    const std::string& where() const { return where_; }
    const std::string& pointer() const { return pointer_; }
    /// 413 for the first key that was not read, with the nearest valid key as
    /// a suggestion and the list of valid keys.
    Result<void> no_unknown_keys() const;

private:
    void mark(const char* key) {
        if (seen_.insert(key).second) order_.emplace_back(key);
    }

    const Json& object_;
    std::string where_;
    std::string pointer_;
    std::set<std::string> seen_;
    std::vector<std::string> order_;  ///< keys in the order the reader asks for them
};

#define NCLINK_TRY(expr)                                         \
    do {                                                         \
        if (auto r_ = (expr); !r_) return std::move(r_).error(); \
    } while (0)

}  // namespace nclink::core_detail
