// nclink-bridge: NC-Link machines through MTConnect 1.4 REST, GB/T 18759.6,
// SHDR and a JSON API (docs/bridge.md). Argument parsing and wiring only; the
// bridge lives in src/bridge/.
//
//   nclink-bridge --broker URL [--device GUID]... [--http HOST:PORT] [--shdr HOST:PORT] [--config FILE]
// Exit codes: 0 clean stop (SIGINT/SIGTERM), 1 cannot run (config, bind), 2 usage.
// SIGHUP re-reads --config (Bridge::reload; docs/bridge.md "Reload").
#include "bridge/bridge.hpp"

#include <nclink/log.hpp>

#include <csignal>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <pthread.h>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace {

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

std::string joined(const std::vector<std::string>& keys) {
    std::string out;
    for (const auto& k : keys) out += (out.empty() ? "" : ", ") + k;
    return out;
}

// SIGHUP: a file that does not read is refused whole; the running
// configuration stays.
void reload(const Options& o, nclink::bridge::Bridge& bridge, const nclink::Logger& logger) {
    if (!o.config_path) {
        logger.warn("nclink-bridge: SIGHUP: no --config file to reload");
        return;
    }
    auto next = effective_config(o);
    if (!next) {
        logger.error("nclink-bridge: reload refused, the running configuration stays: {}", next.error().describe());
        return;
    }
    const nclink::ConfigReload report = bridge.reload(*next);
    if (report.applied.empty() && report.restart_needed.empty())
        logger.info("nclink-bridge: reloaded {}: nothing changed", *o.config_path);
    else if (!report.applied.empty())
        logger.info("nclink-bridge: reloaded {}: applied {}", *o.config_path, joined(report.applied));
    if (!report.restart_needed.empty())
        logger.warn("nclink-bridge: changed in {} but applied only after a restart: {}", *o.config_path,
                    joined(report.restart_needed));
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&](std::optional<std::string>& out) {
            if (i + 1 >= argc) return false;
            out = argv[++i];
            return true;
        };
        auto endpoint = [&](const char* name, std::optional<std::pair<std::string, int>>& out, bool* off) {
            std::optional<std::string> text;
            if (!value(text)) return false;
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
        if (arg == "--broker") ok = value(o.broker);
        else if (arg == "--config") ok = value(o.config_path);
        else if (arg == "--http") ok = endpoint("--http", o.http, nullptr);
        else if (arg == "--shdr") ok = endpoint("--shdr", o.shdr, &o.shdr_off);
        else if (arg == "--log-level") {
            ok = value(o.log_level);
            if (ok && !nclink::log_level_from_string(*o.log_level)) {
                std::cerr << "nclink-bridge: unknown log level " << *o.log_level << "\n";
                ok = false;
            }
        } else if (arg == "--buffer-size") {
            std::optional<std::string> text;
            ok = value(text);
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
        } else if (arg == "--device") {
            std::optional<std::string> d;
            ok = value(d) && !d->empty();
            if (ok) o.devices.push_back(*d);
        } else if (arg == "-h" || arg == "--help") {
            usage(std::cout);
            return 0;
        } else {
            std::cerr << "nclink-bridge: unknown argument " << arg << "\n";
            ok = false;
        }
        if (!ok) {
            usage(std::cerr);
            return 2;
        }
    }
    if (!o.broker && !o.config_path) {
        usage(std::cerr);
        return 2;
    }

    auto effective = effective_config(o);
    if (!effective) {
        std::cerr << "nclink-bridge: " << effective.error().describe() << "\n";
        return 1;
    }
    const nclink::bridge::BridgeConfig config = std::move(effective).value();

    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    nclink::Logger logger(nclink::stderr_sink(), config.log_level);
    nclink::bridge::Bridge bridge(config, logger);
    if (auto started = bridge.start(); !started) {
        std::cerr << "nclink-bridge: " << started.error().describe() << "\n";
        return 1;
    }
    logger.info("nclink-bridge: MTConnect on http://{}:{}/, dashboard on http://{}:{}/dashboard, SHDR on {}:{}; "
                "SIGHUP reloads, SIGINT/SIGTERM stops",
                config.http_host, bridge.http_port(), config.http_host, bridge.http_port(), config.shdr_host,
                bridge.shdr_port());
    int signal_number = 0;
    while (true) {
        sigwait(&signals, &signal_number);
        if (signal_number != SIGHUP) break;
        reload(o, bridge, logger);
    }
    logger.info("nclink-bridge: stopping");
    bridge.stop();
    return 0;
}
