#include <nclink/log.hpp>

#include <chrono>
#include <cstdio>
#include <ctime>
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
        const auto now = system_clock::now();
        const std::time_t seconds = system_clock::to_time_t(now);
        const auto millis = duration_cast<milliseconds>(now.time_since_epoch()).count() % 1000;
        std::tm utc{};
        gmtime_r(&seconds, &utc);
        char stamp[32];
        std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", &utc);
        // One fwrite per line: stdio locks the stream, so lines never interleave.
        const std::string line =
            fmt::format("{}.{:03}Z {:<5} {}\n", stamp, millis, to_string(level), message);
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
