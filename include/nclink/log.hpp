// Pluggable logging. Firmware has its own logger, so nclink never writes to a
// global; every component logs through the Logger its owner hands it.
#pragma once

#include <nclink/export.hpp>
#include <fmt/format.h>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>

namespace nclink {

enum class LogLevel { trace = 0, debug, info, warn, error, off };

NCLINK_API std::string_view to_string(LogLevel level) noexcept;
/// "trace"/"debug"/"info"/"warn" (or "warning")/"error"/"off"; nullopt otherwise.
NCLINK_API std::optional<LogLevel> log_level_from_string(std::string_view text);

/// Receives one formatted message (no trailing newline).
/// Thread: called on whichever SDK thread logs, possibly several at once;
/// a sink must be thread-safe. It must not call back into nclink.
using LogSink = std::function<void(LogLevel, std::string_view message)>;

/// A sink writing "2026-11-21T10:00:00.123Z info  message" lines to stderr,
/// one write per line so concurrent lines do not interleave.
NCLINK_API LogSink stderr_sink();

/// Cheap to copy; copies share the sink and the level. Thread-safe to use
/// from many threads as long as the sink is.
class NCLINK_API Logger {
public:
    /// A logger that drops everything.
    Logger() = default;
    Logger(LogSink sink, LogLevel min_level = LogLevel::info)
        : sink_(std::make_shared<LogSink>(std::move(sink))), min_level_(std::make_shared<std::atomic<LogLevel>>(min_level)) {}

    bool enabled(LogLevel level) const noexcept { return sink_ && *sink_ && level >= min_level() && level != LogLevel::off; }
    LogLevel min_level() const noexcept { return min_level_ ? min_level_->load(std::memory_order_relaxed) : LogLevel::info; }
    /// Changes the level of this logger and of every copy of it (a program
    /// reloading its configuration on SIGHUP changes what every component
    /// logs). Thread-safe; no effect on a logger that drops everything.
    void set_min_level(LogLevel level) const noexcept {
        if (min_level_) min_level_->store(level, std::memory_order_relaxed);
    }

    template <class... Args>
    void log(LogLevel level, fmt::format_string<Args...> format, Args&&... args) const {
        if (!enabled(level)) return;
        write(level, fmt::vformat(format, fmt::make_format_args(args...)));
    }
    template <class... Args>
    void trace(fmt::format_string<Args...> f, Args&&... a) const {
        log(LogLevel::trace, f, std::forward<Args>(a)...);
    }
    template <class... Args>
    void debug(fmt::format_string<Args...> f, Args&&... a) const {
        log(LogLevel::debug, f, std::forward<Args>(a)...);
    }
    template <class... Args>
    void info(fmt::format_string<Args...> f, Args&&... a) const {
        log(LogLevel::info, f, std::forward<Args>(a)...);
    }
    template <class... Args>
    void warn(fmt::format_string<Args...> f, Args&&... a) const {
        log(LogLevel::warn, f, std::forward<Args>(a)...);
    }
    template <class... Args>
    void error(fmt::format_string<Args...> f, Args&&... a) const {
        log(LogLevel::error, f, std::forward<Args>(a)...);
    }

    void write(LogLevel level, std::string_view message) const {
        if (enabled(level)) (*sink_)(level, message);
    }

private:
    std::shared_ptr<LogSink> sink_;
    std::shared_ptr<std::atomic<LogLevel>> min_level_;
};

}  // namespace nclink
