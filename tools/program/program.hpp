// The skeleton the service programs share (nclink-agent, nclink-bridge,
// nclink-sim): the argument loop, the one-line errors and exit statuses, the
// signals (SIGINT/SIGTERM stop, SIGHUP reloads) and the report of a reload.
// Each program keeps its own options, usage text and wiring; what is the same
// in all of them is here, once. Header-only, so the programs in tools/ and
// examples/ use it whichever of them is built.
#pragma once

#include <nclink/config_reload.hpp>
#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <pthread.h>

#include <chrono>
#include <csignal>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace nclink::program {

/// Exit statuses. 2 is what a systemd unit does not restart on
/// (RestartPreventExitStatus=2): a usage or configuration error stays one.
constexpr int kExitOk = 0;         ///< stopped by SIGINT/SIGTERM, or done
constexpr int kExitCannotRun = 1;  ///< cannot start (a port, the broker, the driver)
constexpr int kExitUsage = 2;      ///< usage or configuration error

/// "program: message" on standard error; returns `status` for main() to return.
inline int fail(const char* program, const std::string& message, int status) {
    std::cerr << program << ": " << message << "\n";
    return status;
}

/// The command line read front to back: "--name VALUE" options and flags.
///
///     for (Arguments args(argc, argv); args.next();) {
///         if (args.is("--broker")) ok = args.value(o.broker);
///         else if (args.help()) ...
///     }
class Arguments {
public:
    Arguments(int argc, char** argv) : argc_(argc), argv_(argv) {}

    /// Moves to the next argument; false when there is none left.
    bool next() {
        if (index_ + 1 >= argc_) return false;
        current_ = argv_[++index_];
        return true;
    }
    const std::string& current() const noexcept { return current_; }
    bool is(const char* name) const { return current_ == name; }
    bool help() const { return current_ == "-h" || current_ == "--help"; }
    /// Whether the current option has a value after it.
    bool has_value() const noexcept { return index_ + 1 < argc_; }
    /// Takes the argument after the current one as its value; false (and
    /// `out` unchanged) when the command line ends first.
    bool value(std::string& out) {
        if (!has_value()) return false;
        out = argv_[++index_];
        return true;
    }
    bool value(std::optional<std::string>& out) {
        std::string text;
        if (!value(text)) return false;
        out = std::move(text);
        return true;
    }

private:
    int argc_;
    char** argv_;
    int index_ = 0;
    std::string current_;
};

/// Keys as one line: "a, b, c".
inline std::string joined(const std::vector<std::string>& keys) {
    std::string out;
    for (const auto& k : keys) out += (out.empty() ? "" : ", ") + k;
    return out;
}

/// The signals a service program answers, blocked in the constructing thread
/// and so in every thread it starts afterwards: construct it before any
/// thread starts, so that only wait() sees them.
class Signals {
public:
    Signals() {
        sigemptyset(&set_);
        sigaddset(&set_, SIGINT);
        sigaddset(&set_, SIGTERM);
        sigaddset(&set_, SIGHUP);
        pthread_sigmask(SIG_BLOCK, &set_, nullptr);
    }
    Signals(const Signals&) = delete;
    Signals& operator=(const Signals&) = delete;

    /// Waits for SIGINT or SIGTERM and returns which; each SIGHUP before it
    /// calls `on_hup` (the reload) on this thread.
    template <class OnHup>
    int serve(OnHup&& on_hup) const {
        int signal_number = 0;
        while (true) {
            sigwait(&set_, &signal_number);
            if (signal_number != SIGHUP) return signal_number;
            on_hup();
        }
    }

    static const char* name(int signal_number) { return signal_number == SIGINT ? "SIGINT" : "SIGTERM"; }

private:
    sigset_t set_;
};

/// The reload report every program logs after SIGHUP (docs/configuration.md,
/// "Reloading"): what applies now, what waits for a restart.
inline void log_reload(const Logger& logger, const char* program, const std::string& file, const ConfigReload& report) {
    if (report.applied.empty() && report.restart_needed.empty()) logger.info("{}: reloaded {}: nothing changed", program, file);
    else if (!report.applied.empty()) logger.info("{}: reloaded {}: applied {}", program, file, joined(report.applied));
    if (!report.restart_needed.empty())
        logger.warn("{}: changed in {} but applied only after a restart: {}", program, file, joined(report.restart_needed));
}

/// SIGHUP without a configuration file: nothing to read again.
inline void log_nothing_to_reload(const Logger& logger, const char* program, const char* what = "--config file") {
    logger.warn("{}: SIGHUP: no {} to reload", program, what);
}

/// A file that does not read (or a configuration the program refuses): the
/// running configuration stays.
inline void log_reload_refused(const Logger& logger, const char* program, const std::string& why) {
    logger.error("{}: reload refused, the running configuration stays: {}", program, why);
}

/// After start(): waits (up to `patience`) for the first connection to the
/// broker. A broker that refuses (credentials, a certificate) will go on
/// refusing: returns why, and the program says so and exits. An unreachable
/// broker is waited for (the caller keeps running): nullopt.
template <class GetStats>
std::optional<std::string> refused_by_broker(GetStats&& transport_stats,
                                             std::chrono::milliseconds patience = std::chrono::seconds(10)) {
    const auto step = std::chrono::milliseconds(50);
    for (auto waited = std::chrono::milliseconds(0); waited < patience; waited += step) {
        const TransportStats link = transport_stats();
        if (link.connects != 0) return std::nullopt;
        if (link.refused) return link.last_error;
        std::this_thread::sleep_for(step);
    }
    return std::nullopt;
}

}  // namespace nclink::program
