// nclink-bridge: NC-Link machines through MTConnect 1.4 REST, GB/T 18759.6,
// SHDR and a JSON API (docs/bridge.md). Argument parsing and wiring only; the
// bridge lives in src/bridge/.
//
//   nclink-bridge --broker URL [--device GUID]... [--http HOST:PORT] [--shdr HOST:PORT] [--config FILE]
// Exit codes: 0 clean stop (SIGINT/SIGTERM), 1 cannot run (config, bind), 2 usage.
// SIGHUP re-reads --config (Bridge::reload; docs/bridge.md "Reload").
#include "bridge/bridge.hpp"
#include "program.hpp"

#include <nclink/log.hpp>

#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace {

using nclink::program::kExitCannotRun;
using nclink::program::kExitUsage;
constexpr const char* kProgram = "nclink-bridge";

void usage(std::ostream& out) {
    out << "usage: nclink-bridge --broker URL [--device GUID]... [--http HOST:PORT] [--shdr HOST:PORT|off]\n"
           "                     [--config FILE] [--buffer-size N] [--log-level LEVEL]\n"
           "Serves NC-Link machines as MTConnect 1.4 (http://HOST:PORT/probe, /current, /sample),\n"
           "GB/T 18759.6 (/gbt18759/...), SHDR (TCP) and JSON (/nclink/v1/...), with a web\n"
           "dashboard at /dashboard and Prometheus metrics at /metrics. Without --device\n"
           "every adapter on the broker is followed. Defaults: --http 127.0.0.1:5000,\n"
           "--shdr 127.0.0.1:7878, --buffer-size 131072. An --http address other than\n"
           "loopback needs http_username and http_password in the configuration file.\n"
           "SIGHUP re-reads --config: log_level applies at once, other keys at the next start.\n"
           "See docs/bridge.md, docs/dashboard.md, docs/metrics.md.\n";
}

// What the command line says; its values are checked before anything runs.
struct Options {
    std::optional<std::string> broker, config_path, log_level;
    std::optional<std::pair<std::string, int>> http, shdr;
    bool shdr_off = false;
    std::optional<std::size_t> buffer_size;
    std::vector<std::string> devices;
};

// The file's configuration with the command line on top: the same at start
// and at every reload, so a reload sees only what changed in the file.
nclink::Result<nclink::bridge::BridgeConfig> effective_config(const Options& o) {
    nclink::bridge::BridgeConfig config;
    if (o.config_path) {
        auto loaded = nclink::bridge::load_bridge_config(*o.config_path);
        if (!loaded) return std::move(loaded).error();
        config = std::move(loaded).value();
    }
    if (o.broker) config.broker_url = *o.broker;
    if (!o.devices.empty()) config.devices = o.devices;
    if (o.http) std::tie(config.http_host, config.http_port) = *o.http;
    if (o.shdr_off) config.shdr_enabled = false;
    if (o.shdr) std::tie(config.shdr_host, config.shdr_port) = *o.shdr;
    if (o.buffer_size) config.buffer_size = *o.buffer_size;
    if (o.log_level) config.log_level = *nclink::log_level_from_string(*o.log_level);
    return config;
}

// SIGHUP: a file that does not read is refused whole; the running
// configuration stays.
void reload(const Options& o, nclink::bridge::Bridge& bridge, const nclink::Logger& logger) {
    if (!o.config_path) return nclink::program::log_nothing_to_reload(logger, kProgram);
    auto next = effective_config(o);
    if (!next) return nclink::program::log_reload_refused(logger, kProgram, next.error().describe());
    nclink::program::log_reload(logger, kProgram, *o.config_path, bridge.reload(*next));
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (nclink::program::Arguments args(argc, argv); args.next();) {
        auto endpoint = [&](const char* name, std::optional<std::pair<std::string, int>>& out, bool* off) {
            std::optional<std::string> text;
            if (!args.value(text)) return false;
            if (off && *text == "off") {
                *off = true;
                return true;
            }
            auto hp = nclink::bridge::parse_host_port(*text);
            if (!hp) {
                std::cerr << "nclink-bridge: " << name << " " << hp.error().message << "\n";
                return false;
            }
            out = *hp;
            return true;
        };
        bool ok = true;
        if (args.is("--broker")) ok = args.value(o.broker);
        else if (args.is("--config")) ok = args.value(o.config_path);
        else if (args.is("--http")) ok = endpoint("--http", o.http, nullptr);
        else if (args.is("--shdr")) ok = endpoint("--shdr", o.shdr, &o.shdr_off);
        else if (args.is("--log-level")) {
            ok = args.value(o.log_level);
            if (ok && !nclink::log_level_from_string(*o.log_level)) {
                std::cerr << "nclink-bridge: unknown log level " << *o.log_level << "\n";
                ok = false;
            }
        } else if (args.is("--buffer-size")) {
            std::optional<std::string> text;
            ok = args.value(text);
            if (ok) {
                char* end = nullptr;
                const unsigned long long n = std::strtoull(text->c_str(), &end, 10);
                if (text->empty() || *end != '\0' || n < 1 || n > (1ull << 26)) {
                    std::cerr << "nclink-bridge: --buffer-size must be 1..67108864\n";
                    ok = false;
                } else {
                    o.buffer_size = static_cast<std::size_t>(n);
                }
            }
        } else if (args.is("--device")) {
            std::optional<std::string> d;
            ok = args.value(d) && !d->empty();
            if (ok) o.devices.push_back(*d);
        } else if (args.help()) {
            usage(std::cout);
            return nclink::program::kExitOk;
        } else {
            std::cerr << kProgram << ": unknown argument " << args.current() << "\n";
            ok = false;
        }
        if (!ok) {
            usage(std::cerr);
            return kExitUsage;
        }
    }
    if (!o.broker && !o.config_path) {
        usage(std::cerr);
        return kExitUsage;
    }

    // A configuration that does not read stops here: status 1, the bridge
    // cannot run (the exit codes above).
    auto effective = effective_config(o);
    if (!effective) return nclink::program::fail(kProgram, effective.error().describe(), kExitCannotRun);
    const nclink::bridge::BridgeConfig config = std::move(effective).value();

    const nclink::program::Signals signals;  // before any thread starts

    nclink::Logger logger(nclink::stderr_sink(), config.log_level);
    nclink::bridge::Bridge bridge(config, logger);
    if (auto started = bridge.start(); !started)
        return nclink::program::fail(kProgram, started.error().describe(), kExitCannotRun);
    logger.info(
        "nclink-bridge: MTConnect on http://{}:{}/, dashboard on http://{}:{}/dashboard, SHDR on {}:{}; "
        "SIGHUP reloads, SIGINT/SIGTERM stops",
        config.http_host, bridge.http_port(), config.http_host, bridge.http_port(), config.shdr_host, bridge.shdr_port());
    signals.serve([&] { reload(o, bridge, logger); });
    logger.info("nclink-bridge: stopping");
    bridge.stop();
    return nclink::program::kExitOk;
}
