// Doubles that are short decimals (at most 6 fraction digits: positions in
// mm, speeds, loads, the bulk of CNC data) written as text without the
// general shortest-digits search: several times cheaper than it (nlohmann's
// grisu2 ~150 ns a value on the reference VM, this ~25 ns).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>

namespace nclink::protocol_detail {

/// Writes `value` in fixed notation ("-12.5", "0.000123") when it is the
/// double nearest to a decimal with at most 6 fraction digits and lies in
/// (-2^32, 2^32); returns the end of the text, or nullptr (nothing written
/// that counts) for any other value. Below 2^32 a double's spacing is under
/// 1e-6, so at most one such decimal maps to `value`; if n / 1e6 == value
/// (a correctly rounded division, like a parser's rounding of the decimal)
/// then that decimal is the shortest text that reads back to `value`.
/// Integral values are written without a fraction ("414"). `out` needs 24 bytes.
inline char* write_short_decimal(char* out, double value) noexcept {
    if (!(value > -4294967296.0 && value < 4294967296.0)) return nullptr;
    const auto n = static_cast<std::int64_t>(std::nearbyint(value * 1e6));
    if (static_cast<double>(n) / 1e6 != value) return nullptr;
    const std::uint64_t magnitude = n < 0 ? static_cast<std::uint64_t>(-n) : static_cast<std::uint64_t>(n);
    if (n < 0) *out++ = '-';
    out = std::to_chars(out, out + 16, magnitude / 1000000).ptr;
    auto fraction = static_cast<std::uint32_t>(magnitude % 1000000);
    if (fraction == 0) return out;
    int digits = 6;
    while (fraction % 10 == 0) {
        fraction /= 10;
        --digits;
    }
    *out++ = '.';
    for (int i = digits - 1; i >= 0; --i) {
        out[i] = static_cast<char>('0' + fraction % 10);
        fraction /= 10;
    }
    return out + digits;
}

}  // namespace nclink::protocol_detail
