// nclink-bridge: NC-Link machines through MTConnect 1.4 REST, GB/T 18759.6,
// SHDR and a JSON API (docs/bridge.md). Argument parsing and wiring only; the
// bridge lives in src/bridge/.
//
//   nclink-bridge --broker URL [--device GUID]... [--http HOST:PORT] [--shdr HOST:PORT] [--config FILE]
// Exit codes: 0 clean stop (SIGINT/SIGTERM), 1 cannot run (config, bind), 2 usage.
#include "bridge/bridge.hpp"

#include <nclink/log.hpp>

#include <csignal>
#include <iostream>
#include <optional>
#include <pthread.h>
#include <string>
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
           "See docs/bridge.md, docs/dashboard.md, docs/metrics.md.\n";
}

}  // namespace

int main(int argc, char** argv) {
    std::optional<std::string> broker, config_path, http, shdr, log_level, buffer_size;
    std::vector<std::string> devices;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&](std::optional<std::string>& out) {
            if (i + 1 >= argc) return false;
            out = argv[++i];
            return true;
        };
        bool ok = true;
        if (arg == "--broker") ok = value(broker);
        else if (arg == "--config") ok = value(config_path);
        else if (arg == "--http") ok = value(http);
        else if (arg == "--shdr") ok = value(shdr);
        else if (arg == "--log-level") ok = value(log_level);
        else if (arg == "--buffer-size") ok = value(buffer_size);
        else if (arg == "--device") {
            std::optional<std::string> d;
            ok = value(d) && !d->empty();
            if (ok) devices.push_back(*d);
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
    if (!broker && !config_path) {
        usage(std::cerr);
        return 2;
    }

    using nclink::bridge::BridgeConfig;
    BridgeConfig config;
    if (config_path) {
        auto loaded = nclink::bridge::load_bridge_config(*config_path);
        if (!loaded) {
            std::cerr << "nclink-bridge: " << loaded.error().describe() << "\n";
            return 1;
        }
        config = std::move(loaded).value();
    }
    if (broker) config.broker_url = *broker;
    if (!devices.empty()) config.devices = devices;
    if (http) {
        auto hp = nclink::bridge::parse_host_port(*http);
        if (!hp) {
            std::cerr << "nclink-bridge: --http " << hp.error().message << "\n";
            return 2;
        }
        config.http_host = hp->first;
        config.http_port = hp->second;
    }
    if (shdr) {
        if (*shdr == "off") {
            config.shdr_enabled = false;
        } else {
            auto hp = nclink::bridge::parse_host_port(*shdr);
            if (!hp) {
                std::cerr << "nclink-bridge: --shdr " << hp.error().message << "\n";
                return 2;
            }
            config.shdr_host = hp->first;
            config.shdr_port = hp->second;
        }
    }
    if (buffer_size) {
        char* end = nullptr;
        const unsigned long long n = std::strtoull(buffer_size->c_str(), &end, 10);
        if (buffer_size->empty() || *end != '\0' || n < 1 || n > (1ull << 26)) {
            std::cerr << "nclink-bridge: --buffer-size must be 1..67108864\n";
            return 2;
        }
        config.buffer_size = static_cast<std::size_t>(n);
    }
    if (log_level) {
        auto level = nclink::log_level_from_string(*log_level);
        if (!level) {
            std::cerr << "nclink-bridge: unknown log level " << *log_level << "\n";
            return 2;
        }
        config.log_level = *level;
    }

    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    nclink::Logger logger(nclink::stderr_sink(), config.log_level);
    nclink::bridge::Bridge bridge(config, logger);
    if (auto started = bridge.start(); !started) {
        std::cerr << "nclink-bridge: " << started.error().describe() << "\n";
        return 1;
    }
    logger.info("nclink-bridge: MTConnect on http://{}:{}/, dashboard on http://{}:{}/dashboard, SHDR on {}:{}; "
                "SIGINT/SIGTERM stops",
                config.http_host, bridge.http_port(), config.http_host, bridge.http_port(), config.shdr_host,
                bridge.shdr_port());
    int signal_number = 0;
    sigwait(&signals, &signal_number);
    logger.info("nclink-bridge: stopping");
    bridge.stop();
    return 0;
}
