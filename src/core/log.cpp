#include <nclink/log.hpp>

#include "core/utc_time.hpp"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace nclink {

std::string_view to_string(LogLevel level) noexcept {
    switch (level) {
        case LogLevel::trace: return "trace";
        case LogLevel::debug: return "debug";
        case LogLevel::info: return "info";
        case LogLevel::warn: return "warn";
        case LogLevel::error: return "error";
        case LogLevel::off: return "off";
    }
    return "?";
}

LogSink stderr_sink() {
    return [](LogLevel level, std::string_view message) {
        using namespace std::chrono;
        // int64 milliseconds, never time_t: 32 bits on Debian 12 armhf.
        const std::int64_t now_ms = duration_cast<milliseconds>(system_clock::now().time_since_epoch()).count();
        // One fwrite per line: stdio locks the stream, so lines never interleave.
        const std::string line = fmt::format("{} {:<5} {}\n", core_detail::utc_iso8601_ms(now_ms), to_string(level), message);
        std::fwrite(line.data(), 1, line.size(), stderr);
    };
}

std::optional<LogLevel> log_level_from_string(std::string_view text) {
    for (LogLevel level : {LogLevel::trace, LogLevel::debug, LogLevel::info, LogLevel::warn, LogLevel::error, LogLevel::off})
        if (to_string(level) == text) return level;
    if (text == "warning") return LogLevel::warn;
    return std::nullopt;
}

}  // namespace nclink
