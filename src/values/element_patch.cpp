// Writing one element: plain replacement under the type rule, or a partial
// write with offset/length (code points of a string, elements of an array,
// bits of an integer register). See SetParams in values.hpp.
#include "values/value_internal.hpp"

#include <cmath>
#include <cstdint>

namespace nclink::values_detail {
namespace {

// Code points are counted by their lead bytes, so even a string that is not
// valid UTF-8 (set by local code) is handled without failing.
bool is_lead(char c) { return (static_cast<unsigned char>(c) & 0xC0U) != 0x80U; }

std::size_t code_points(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += is_lead(c) ? 1 : 0;
    return n;
}

// Byte position of code point `index` (text.size() when index == count).
std::size_t byte_of(const std::string& text, std::size_t index) {
    std::size_t seen = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (!is_lead(text[i])) continue;
        if (seen == index) return i;
        ++seen;
    }
    return text.size();
}

Result<void> check_span(std::size_t offset, std::size_t length, std::size_t size, std::string_view unit, const std::string& where) {
    if (offset > size) return fail(ErrorCode::out_of_range, "offset {} is beyond the {} {} of {}", offset, size, unit, where);
    if (length > size - offset)
        return fail(ErrorCode::out_of_range, "offset {} + length {} is beyond the {} {} of {}", offset, length, size, unit, where);
    return ok_result();
}

Result<Json> patch_string(const std::string& text, const Json& value, std::size_t offset,
                          const std::optional<std::size_t>& length, const std::string& where) {
    if (!value.is_string())
        return fail(ErrorCode::value_type, "a partial write of the string {} needs a string value, got {}", where,
                    json_type_name(value));
    const auto& insert = value.get_ref<const std::string&>();
    const std::size_t count = length.value_or(code_points(insert));
    if (auto span = check_span(offset, count, code_points(text), "characters", where); !span) return std::move(span).error();
    const std::size_t begin = byte_of(text, offset);
    const std::size_t end = byte_of(text, offset + count);
    std::string out;
    out.reserve(text.size() - (end - begin) + insert.size());
    out.append(text, 0, begin).append(insert).append(text, end, std::string::npos);
    return Json(std::move(out));
}

Result<Json> patch_array(const Json& array, const Json& value, std::size_t offset, const std::optional<std::size_t>& length,
                         const std::string& where) {
    // An array value is spliced element by element; anything else is one element.
    const Json insert = value.is_array() ? value : Json::array({value});
    const std::size_t count = length.value_or(insert.size());
    if (auto span = check_span(offset, count, array.size(), "elements", where); !span) return std::move(span).error();
    Json out = Json::array();
    for (std::size_t i = 0; i < offset; ++i) out.push_back(array[i]);
    for (const auto& element : insert) out.push_back(element);
    for (std::size_t i = offset + count; i < array.size(); ++i) out.push_back(array[i]);
    return out;
}

// The integer bits of a register element; 405 for a non-integral number.
Result<std::uint64_t> register_bits(const Json& number, const std::string& where) {
    if (number.is_number_unsigned()) return number.get<std::uint64_t>();
    if (number.is_number_integer()) return static_cast<std::uint64_t>(number.get<std::int64_t>());
    const double d = number.get<double>();
    if (!std::isfinite(d) || d != std::floor(d) || d < -9223372036854775808.0 || d >= 9223372036854775808.0)
        return fail(ErrorCode::value_type, "bit access needs an integer, but {} is {}", where, d);
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(d));
}

// Keeps an unsigned register unsigned, otherwise stores two's complement.
Json register_json(const Json& original, std::uint64_t bits) {
    if (original.is_number_unsigned()) return Json(bits);
    return Json(static_cast<std::int64_t>(bits));
}

Result<Json> patch_bits(const Json& number, const Json& value, const std::optional<std::size_t>& offset,
                        const std::optional<std::size_t>& length, const std::string& where) {
    auto bits = register_bits(number, where);
    if (!bits) return std::move(bits).error();
    const std::size_t at = offset.value_or(0);
    if (!length) {
        // HNC convention: value true / non-zero sets bit `offset`, false / 0 clears it.
        if (at > 63) return fail(ErrorCode::out_of_range, "bit {} is beyond the 64 bits of {}", at, where);
        bool on = false;
        if (value.is_boolean()) on = value.get<bool>();
        else if (value.is_number()) on = value.get<double>() != 0.0;
        else
            return fail(ErrorCode::value_type, "setting bit {} of {} needs a boolean or number, got {}", at, where,
                        json_type_name(value));
        const std::uint64_t mask = std::uint64_t{1} << at;
        return register_json(number, on ? (*bits | mask) : (*bits & ~mask));
    }
    const std::size_t width = *length;
    if (width == 0 || width > 64 || at >= 64 || width > 64 - at)
        return fail(ErrorCode::out_of_range, "bit field offset {} length {} does not fit the 64 bits of {}", at, width, where);
    std::uint64_t field = 0;
    if (value.is_boolean()) {
        field = value.get<bool>() ? 1 : 0;
    } else if (value.is_number_unsigned()) {
        field = value.get<std::uint64_t>();
    } else if (value.is_number_integer()) {
        const auto n = value.get<std::int64_t>();
        if (n < 0) return fail(ErrorCode::out_of_range, "bit field value {} is negative", n);
        field = static_cast<std::uint64_t>(n);
    } else if (value.is_number_float()) {
        const double d = value.get<double>();
        if (!std::isfinite(d) || d != std::floor(d))
            return fail(ErrorCode::value_type, "bit field value {} is not an integer", d);
        if (d < 0 || d >= 18446744073709551616.0) return fail(ErrorCode::out_of_range, "bit field value {} does not fit", d);
        field = static_cast<std::uint64_t>(d);
    } else {
        return fail(ErrorCode::value_type, "a bit field of {} needs an integer value, got {}", where, json_type_name(value));
    }
    const std::uint64_t mask = width == 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << width) - 1);
    if ((field & ~mask) != 0) return fail(ErrorCode::out_of_range, "value {} does not fit a bit field of {} bits", field, width);
    return register_json(number, (*bits & ~(mask << at)) | (field << at));
}

}  // namespace

Result<Json> element_part(const Json& element, const std::optional<std::size_t>& offset, const std::optional<std::size_t>& length,
                          const std::string& where) {
    const std::size_t at = offset.value_or(0);
    if (element.is_string()) {
        const auto& text = element.get_ref<const std::string&>();
        const std::size_t size = code_points(text);
        const std::size_t count = length.value_or(at <= size ? size - at : 0);
        if (auto span = check_span(at, count, size, "characters", where); !span) return std::move(span).error();
        const std::size_t begin = byte_of(text, at);
        return Json(text.substr(begin, byte_of(text, at + count) - begin));
    }
    if (element.is_array()) {
        const std::size_t count = length.value_or(at <= element.size() ? element.size() - at : 0);
        if (auto span = check_span(at, count, element.size(), "elements", where); !span) return std::move(span).error();
        Json out = Json::array();
        for (std::size_t i = at; i < at + count; ++i) out.push_back(element[i]);
        return out;
    }
    if (element.is_number()) {
        auto bits = register_bits(element, where);
        if (!bits) return std::move(bits).error();
        const std::size_t width = length.value_or(1);
        if (width == 0 || width > 64 || at >= 64 || width > 64 - at)
            return fail(ErrorCode::out_of_range, "bit field offset {} length {} does not fit the 64 bits of {}", at, width, where);
        const std::uint64_t mask = width == 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << width) - 1);
        return Json((*bits >> at) & mask);
    }
    if (element.is_null()) return fail(ErrorCode::unavailable, "{} is not known", where);
    return fail(ErrorCode::value_type, "offset/length apply to strings, arrays and integers, {} is a {}", where,
                json_type_name(element));
}

Result<Json> patch_element(const Json& element, const Json& value, const std::optional<std::size_t>& offset,
                           const std::optional<std::size_t>& length, const std::string& where) {
    if (!offset && !length) {
        if (!same_value_type(element, value))
            return fail(ErrorCode::value_type, "{} holds a {}, the new value is a {}", where, json_type_name(element),
                        json_type_name(value));
        return value;
    }
    if (element.is_string()) return patch_string(element.get_ref<const std::string&>(), value, offset.value_or(0), length, where);
    if (element.is_array()) return patch_array(element, value, offset.value_or(0), length, where);
    if (element.is_number()) return patch_bits(element, value, offset, length, where);
    if (element.is_null()) return fail(ErrorCode::unavailable, "{} is not known, a partial write needs its current value", where);
    return fail(ErrorCode::value_type, "offset/length apply to strings, arrays and integers, {} is a {}", where,
                json_type_name(element));
}

}  // namespace nclink::values_detail
