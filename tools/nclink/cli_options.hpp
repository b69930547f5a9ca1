// Option parsing shared by the device subcommands of `nclink` (probe, query,
// set, watch, state). Header-only and pure, so the unit tests can call it.
#pragma once

#include "commands.hpp"

#include <chrono>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::cli {

/// The options every device subcommand takes (a macro so each command's usage
/// string can append it at compile time).
#define NCLINK_CLI_GLOBAL_OPTIONS                                                                    \
    "global options:\n"                                                                              \
    "  --broker URL      MQTT broker (default tcp://127.0.0.1:1883)\n"                               \
    "  --failover URL    another broker to fail over to (host:port or a URL; repeat for more)\n"     \
    "  --device GUID     the adapter's terminal id (dev_uuid); required\n"                           \
    "  --client-id ID    this application's terminal id (default nclink-cli-<pid>)\n"                \
    "  --timeout MS      per-request timeout and broker connect timeout (default 2000)\n"            \
    "  --username NAME   broker user name (the ACL expects the terminal id, see docs/security.md)\n" \
    "  --password-file F broker password: first line of F (or $NCLINK_PASSWORD)\n"                   \
    "  --ca-file PEM     trust these CAs for the broker's certificate (ssl:// URLs)\n"               \
    "  --cert PEM        client certificate, for mutual TLS (--key: its key)\n"                      \
    "  --key PEM         the client certificate's private key\n"                                     \
    "  --insecure        do not check the broker's certificate (tests only)\n"                       \
    "  --json            machine-readable output\n"                                                  \
    "  --persistent      keep the broker session (clean_session=false) under --client-id:\n"         \
    "                    QoS 1 DTUs sent while this command is not running arrive at its next run\n" \
    "exit status: 0 success, 1 an NG or timeout answer (or no broker), 2 usage error\n"

struct CliOptions {
    std::string broker = "tcp://127.0.0.1:1883";
    std::vector<std::string> failover;  ///< --failover, in order (MqttOptions::failover_urls)
    std::string device;
    std::string client_id;  ///< empty = nclink-cli-<pid>, filled in by the caller
    std::chrono::milliseconds timeout{2000};
    std::string username;
    std::string password_file;  ///< "" = $NCLINK_PASSWORD, if set
    std::string ca_file, cert_file, key_file;
    bool insecure = false;
    bool json = false;
    bool persistent = false;  ///< --persistent: clean_session=false (needs --client-id)
    bool help = false;
    std::set<std::string> flags;                ///< command-specific flags given ("--follow")
    std::map<std::string, std::string> values;  ///< command-specific valued options ("--count" -> "5")
    std::vector<std::string> positionals;
};

/// The command-specific options a subcommand accepts.
struct OptionSpec {
    std::set<std::string> flags;
    std::set<std::string> valued;
};

/// A positive (or, with allow_zero, non-negative) decimal integer, else UsageError.
inline std::uint64_t parse_count(std::string_view option, std::string_view text, bool allow_zero = false) {
    std::uint64_t value = 0;
    if (text.empty() || text.size() > 18) throw UsageError{std::string(option) + " needs a number"};
    for (char c : text) {
        if (c < '0' || c > '9') throw UsageError{std::string(option) + " needs a number, not \"" + std::string(text) + "\""};
        value = value * 10 + static_cast<std::uint64_t>(c - '0');
    }
    if (value == 0 && !allow_zero) throw UsageError{std::string(option) + " must be positive"};
    return value;
}

/// Parses `--name value`, `--name=value`, flags and positionals (everything
/// after `--` is positional). Throws UsageError on unknown options and
/// missing or malformed values.
inline CliOptions parse_cli_options(const Args& args, const OptionSpec& spec = {}) {
    static const std::set<std::string> global_valued = {"--broker",   "--failover",      "--device",  "--client-id", "--timeout",
                                                        "--username", "--password-file", "--ca-file", "--cert",      "--key"};
    CliOptions out;
    bool options_done = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (options_done || arg.size() < 2 || arg[0] != '-') {
            out.positionals.push_back(arg);
            continue;
        }
        if (arg == "--") {
            options_done = true;
            continue;
        }
        if (arg == "--help" || arg == "-h") {
            out.help = true;
            continue;
        }
        std::string name = arg;
        std::string value;
        bool has_value = false;
        if (const auto eq = arg.find('='); eq != std::string::npos && arg.rfind("--", 0) == 0) {
            name = arg.substr(0, eq);
            value = arg.substr(eq + 1);
            has_value = true;
        }
        const bool valued = global_valued.count(name) > 0 || spec.valued.count(name) > 0;
        if (valued) {
            if (!has_value) {
                if (i + 1 >= args.size()) throw UsageError{name + " needs a value"};
                value = args[++i];
            }
            if (name == "--broker") {
                if (value.empty()) throw UsageError{"--broker needs a URL"};
                out.broker = value;
            } else if (name == "--failover") {
                if (value.empty()) throw UsageError{"--failover needs a broker (host:port or a URL)"};
                out.failover.push_back(value);
            } else if (name == "--device") {
                out.device = value;
            } else if (name == "--client-id") {
                out.client_id = value;
            } else if (name == "--username") {
                out.username = value;
            } else if (name == "--password-file") {
                out.password_file = value;
            } else if (name == "--ca-file") {
                out.ca_file = value;
            } else if (name == "--cert") {
                out.cert_file = value;
            } else if (name == "--key") {
                out.key_file = value;
            } else if (name == "--timeout") {
                out.timeout = std::chrono::milliseconds(static_cast<std::int64_t>(parse_count(name, value)));
            } else {
                out.values[name] = value;
            }
            continue;
        }
        if (has_value) throw UsageError{name + " takes no value"};
        if (name == "--json") {
            out.json = true;
        } else if (name == "--persistent") {
            out.persistent = true;
        } else if (name == "--insecure") {
            out.insecure = true;
        } else if (spec.flags.count(name) > 0) {
            out.flags.insert(name);
        } else {
            throw UsageError{"unknown option " + arg};
        }
    }
    if (out.persistent && out.client_id.empty())
        throw UsageError{"--persistent needs --client-id (the broker keeps the session under it)"};
    return out;
}

/// A terminal id must be one topic level.
inline void check_terminal_id(std::string_view what, const std::string& id) {
    if (id.empty()) throw UsageError{std::string(what) + " is required"};
    if (id.find_first_of("/+#") != std::string::npos) throw UsageError{std::string(what) + " must not contain '/', '+' or '#'"};
}

}  // namespace nclink::cli
