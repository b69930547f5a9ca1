#include "core/utc_time.hpp"

#include <fmt/format.h>

namespace nclink::core_detail {

namespace {

/// Division rounding towards minus infinity (times before 1970 are negative).
constexpr std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    return a / b - ((a % b != 0) && ((a < 0) != (b < 0)) ? 1 : 0);
}

}  // namespace

std::string utc_iso8601_ms(std::int64_t ms) {
    const std::int64_t seconds = floor_div(ms, 1000);
    const auto millis = static_cast<int>(ms - seconds * 1000);
    const std::int64_t days = floor_div(seconds, 86400);
    const auto second_of_day = static_cast<int>(seconds - days * 86400);

    // Counted from 2000-03-01: a year that starts in March ends with the leap
    // day, so every block below ends with its longer part. 11017 days lie
    // between 1970-01-01 and 2000-03-01.
    const std::int64_t from_2000_march = days - 11017;
    const std::int64_t cycles = floor_div(from_2000_march, 146097);   // 400 years
    auto rest = static_cast<int>(from_2000_march - cycles * 146097);  // [0, 146096]
    int centuries = rest / 36524;                                     // the 4th century has the extra day (2400-02-29)
    if (centuries == 4) centuries = 3;
    rest -= centuries * 36524;
    const int quads = rest / 1461;  // 4-year blocks, the last year of each leap
    rest -= quads * 1461;
    int years = rest / 365;
    if (years == 4) years = 3;  // the leap day itself
    rest -= years * 365;        // day of the March-based year, [0, 365]

    std::int64_t year = 2000 + cycles * 400 + centuries * 100 + quads * 4 + years;
    static constexpr int kMonthDays[12] = {31, 30, 31, 30, 31, 31, 30, 31, 30, 31, 31, 29};  // March .. February
    int month = 0;
    while (rest >= kMonthDays[month]) rest -= kMonthDays[month++];
    month += 3;
    if (month > 12) {
        month -= 12;
        ++year;
    }
    return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", year, month, rest + 1, second_of_day / 3600,
                       second_of_day / 60 % 60, second_of_day % 60, millis);
}

}  // namespace nclink::core_detail
