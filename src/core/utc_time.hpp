// A wall-clock time in milliseconds since 1970 (UTC) as ISO 8601 text,
// without time_t: Debian 12's armhf has a 32-bit time_t, which gmtime_r
// cannot take past 2038-01-19T03:14:07Z (a log line would then say 1901).
// The SDK keeps wall-clock times as std::int64_t milliseconds everywhere.
#pragma once

#include <cstdint>
#include <string>

namespace nclink::core_detail {

/// "2026-12-03T08:15:00.123Z" (proleptic Gregorian calendar; times before
/// 1970 too). Allocates only the returned string.
std::string utc_iso8601_ms(std::int64_t ms_since_epoch);

}  // namespace nclink::core_detail
