// Index and count parameters: `index`/`indexes` entries ("5", 5, "5-8"),
// `offset` and `length`.
#include "values/value_internal.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

namespace nclink {
namespace values_detail {
namespace {

std::string_view trim(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
    return text;
}

bool all_digits(std::string_view text) {
    if (text.empty()) return false;
    for (char c : text)
        if (c < '0' || c > '9') return false;
    return true;
}

// Decimal digits -> size_t; false on overflow.
bool to_size(std::string_view digits, std::size_t& out) {
    constexpr auto max = std::numeric_limits<std::size_t>::max();
    std::size_t value = 0;
    for (char c : digits) {
        const auto digit = static_cast<std::size_t>(c - '0');
        if (value > (max - digit) / 10) return false;
        value = value * 10 + digit;
    }
    out = value;
    return true;
}

}  // namespace

Result<std::size_t> parse_count(const Json& value, std::string_view what) {
    if (value.is_number_unsigned()) {
        const auto n = value.get<std::uint64_t>();
        if (n > std::numeric_limits<std::size_t>::max()) return fail(ErrorCode::out_of_range, "{} {} is too large", what, n);
        return static_cast<std::size_t>(n);
    }
    if (value.is_number_integer()) {
        const auto n = value.get<std::int64_t>();
        if (n < 0) return fail(ErrorCode::out_of_range, "{} {} is negative", what, n);
        return static_cast<std::size_t>(n);
    }
    if (value.is_number_float()) {
        const double d = value.get<double>();
        if (!std::isfinite(d) || d != std::floor(d)) return fail(ErrorCode::value_type, "{} must be an integer, got {}", what, d);
        if (d < 0) return fail(ErrorCode::out_of_range, "{} {} is negative", what, d);
        // 2^64 as a double; anything at or above it does not fit.
        if (d >= 18446744073709551616.0 || d > static_cast<double>(std::numeric_limits<std::size_t>::max()))
            return fail(ErrorCode::out_of_range, "{} {} is too large", what, d);
        return static_cast<std::size_t>(d);
    }
    if (value.is_string()) {
        const std::string_view text = trim(value.get_ref<const std::string&>());
        if (!text.empty() && text.front() == '-' && all_digits(text.substr(1)))
            return fail(ErrorCode::out_of_range, "{} \"{}\" is negative", what, text);
        if (!all_digits(text)) return fail(ErrorCode::value_type, "{} \"{}\" is not a number", what, text);
        std::size_t n = 0;
        if (!to_size(text, n)) return fail(ErrorCode::out_of_range, "{} \"{}\" is too large", what, text);
        return n;
    }
    return fail(ErrorCode::value_type, "{} must be a number or a numeric string, got {}", what, json_type_name(value));
}

}  // namespace values_detail

using values_detail::fail;

std::size_t IndexRange::count() const noexcept {
    if (last < first) return 0;
    const std::size_t span = last - first;
    return span == std::numeric_limits<std::size_t>::max() ? span : span + 1;
}

Result<IndexRange> parse_index(const Json& entry) {
    if (!entry.is_string()) {
        auto n = values_detail::parse_count(entry, "index");
        if (!n) return std::move(n).error();
        return IndexRange{*n, *n};
    }
    const std::string_view text = values_detail::trim(entry.get_ref<const std::string&>());
    const auto dash = text.find('-');
    if (dash == std::string_view::npos) {
        if (!values_detail::all_digits(text)) return fail(ErrorCode::value_type, "index \"{}\" is not a number", text);
        std::size_t n = 0;
        if (!values_detail::to_size(text, n)) return fail(ErrorCode::out_of_range, "index \"{}\" is too large", text);
        return IndexRange{n, n};
    }
    // A range "first-last": both ends required, digits only, first <= last.
    const auto first_text = values_detail::trim(text.substr(0, dash));
    const auto last_text = values_detail::trim(text.substr(dash + 1));
    if (!values_detail::all_digits(first_text) || !values_detail::all_digits(last_text))
        return fail(ErrorCode::syntax_error, "index range \"{}\" is not of the form \"first-last\"", text);
    IndexRange range;
    if (!values_detail::to_size(first_text, range.first) || !values_detail::to_size(last_text, range.last))
        return fail(ErrorCode::out_of_range, "index range \"{}\" is too large", text);
    if (range.first > range.last) return fail(ErrorCode::syntax_error, "index range \"{}\" ends before it starts", text);
    return range;
}

std::size_t index_count(const std::vector<IndexRange>& ranges) noexcept {
    constexpr auto max = std::numeric_limits<std::size_t>::max();
    std::size_t total = 0;
    for (const auto& range : ranges) {
        const auto n = range.count();
        total = (total > max - n) ? max : total + n;
    }
    return total;
}

Result<std::vector<std::size_t>> expand_indexes(const std::vector<IndexRange>& ranges, std::size_t length) {
    for (const auto& range : ranges) {
        if (range.last >= length) {
            const auto bad = range.first >= length ? range.first : range.last;
            return fail(ErrorCode::out_of_range, "index {} is beyond the list length {}", bad, length);
        }
    }
    const std::size_t total = index_count(ranges);
    if (total > max_selected_indexes)
        return fail(ErrorCode::memory_configured, "{} indexes selected, at most {} are served", total, max_selected_indexes);
    std::vector<std::size_t> out;
    out.reserve(total);
    for (const auto& range : ranges)
        for (std::size_t i = range.first; i <= range.last; ++i) out.push_back(i);
    return out;
}

}  // namespace nclink
