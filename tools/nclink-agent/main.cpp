// nclink-agent: runs the NC-Link agent beside an MQTT broker (docs/agent.md).
// Argument parsing and wiring only; the agent lives in src/agent/.
//
//   nclink-agent --broker URL [--config FILE] [--state-dir DIR] [--log-level L] [--metrics HOST:PORT]
//   nclink-agent [--config FILE] --write-mosquitto-acl FILE
//   nclink-agent --config FILE --check-config
//
// SIGHUP re-reads --config and applies what can change while running
// (docs/configuration.md, "Reloading"); a file with a problem is refused and
// the running configuration stays. Exit status: 0 after SIGINT/SIGTERM,
// 1 when the agent cannot start, 2 for usage or configuration errors (a
// systemd unit does not restart on those: RestartPreventExitStatus=2).
#include "http/metrics_endpoint.hpp"

#include <nclink/agent.hpp>
#include <nclink/agent_metrics.hpp>
#include <nclink/log.hpp>
#include <nclink/mqtt_transport.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <pthread.h>
#include <unistd.h>
#include <string>
#include <thread>

namespace {

constexpr int kExitUsage = 2;  // usage and configuration errors

void usage(std::ostream& out) {
    out << "usage: nclink-agent --broker URL [--config FILE] [--state-dir DIR] [--log-level LEVEL]\n"
           "                    [--metrics HOST:PORT [--metrics-user USER]]\n"
           "       nclink-agent [--config FILE] --write-mosquitto-acl FILE\n"
           "       nclink-agent --config FILE --check-config\n"
           "Runs the NC-Link agent (registration, discovery, state, version cache,\n"
           "DEV_UNREACHABLE/timeouts, access control) until SIGINT/SIGTERM. SIGHUP\n"
           "re-reads FILE: registration, access, timeouts and log_level apply at once,\n"
           "the rest at the next start; a broken file is refused and logged.\n"
           "--write-mosquitto-acl writes a mosquitto acl_file enforcing the configured\n"
           "access rules and exits. --check-config reads FILE and exits (0 valid,\n"
           "2 not). Exit status 2: usage or configuration error. See docs/agent.md.\n"
           "--metrics serves Prometheus metrics at http://HOST:PORT/metrics (off by\n"
           "default; docs/metrics.md). A HOST other than loopback needs --metrics-user\n"
           "and the password in the environment variable NCLINK_METRICS_PASSWORD.\n";
}

struct Options {
    std::optional<std::string> broker, config_path, state_dir, log_level, acl_path, metrics, metrics_user;
    bool check_only = false;
};

// The file's configuration with the command line's options on top.
nclink::Result<nclink::AgentConfig> effective_config(const Options& o) {
    nclink::AgentConfig config;
    if (o.config_path) {
        auto loaded = nclink::load_agent_config(*o.config_path);
        if (!loaded) return std::move(loaded).error();
        config = std::move(loaded).value();
    }
    if (o.broker) config.broker_url = *o.broker;
    if (o.state_dir) config.state_dir = *o.state_dir;
    if (o.log_level) config.log_level = *nclink::log_level_from_string(*o.log_level);
    return config;
}

std::string joined(const std::vector<std::string>& keys) {
    std::string out;
    for (const auto& k : keys) out += (out.empty() ? "" : ", ") + k;
    return out;
}

void reload(const Options& o, nclink::Agent& agent, const nclink::Logger& logger) {
    if (!o.config_path) {
        logger.warn("nclink-agent: SIGHUP: no --config file to reload");
        return;
    }
    auto next = effective_config(o);
    if (!next) {
        logger.error("nclink-agent: reload refused, the running configuration stays: {}", next.error().message);
        return;
    }
    auto report = agent.reload(*next);
    if (!report) {
        logger.error("nclink-agent: reload refused, the running configuration stays: {}", report.error().describe());
        return;
    }
    if (report->applied.empty() && report->restart_needed.empty())
        logger.info("nclink-agent: reloaded {}: nothing changed", *o.config_path);
    else if (!report->applied.empty())
        logger.info("nclink-agent: reloaded {}: applied {}", *o.config_path, joined(report->applied));
    if (!report->restart_needed.empty())
        logger.warn("nclink-agent: changed in {} but applied only after a restart: {}", *o.config_path,
                    joined(report->restart_needed));
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
        bool ok = true;
        if (arg == "--broker") ok = value(o.broker);
        else if (arg == "--config") ok = value(o.config_path);
        else if (arg == "--state-dir") ok = value(o.state_dir);
        else if (arg == "--log-level") ok = value(o.log_level);
        else if (arg == "--write-mosquitto-acl") ok = value(o.acl_path);
        else if (arg == "--metrics") ok = value(o.metrics);
        else if (arg == "--metrics-user") ok = value(o.metrics_user);
        else if (arg == "--check-config") o.check_only = true;
        else if (arg == "-h" || arg == "--help") {
            usage(std::cout);
            return 0;
        } else {
            std::cerr << "nclink-agent: unknown argument " << arg << "\n";
            ok = false;
        }
        if (!ok) {
            usage(std::cerr);
            return kExitUsage;
        }
    }
    if (o.log_level && !nclink::log_level_from_string(*o.log_level)) {
        std::cerr << "nclink-agent: unknown log level " << *o.log_level << "\n";
        return kExitUsage;
    }
    if (o.check_only && !o.config_path) {
        std::cerr << "nclink-agent: --check-config needs --config FILE\n";
        return kExitUsage;
    }

    // A configuration with a problem stops here, before anything is started
    // or written: one line naming the file, line and column.
    auto loaded = effective_config(o);
    if (!loaded) {
        std::cerr << "nclink-agent: " << loaded.error().message << "\n";
        return kExitUsage;
    }
    nclink::AgentConfig config = std::move(loaded).value();
    if (o.check_only) {
        std::cout << *o.config_path << ": OK\n";
        return 0;
    }

    if (o.acl_path) {
        std::ofstream out(*o.acl_path);
        out << nclink::mosquitto_acl(config);
        if (!out.good()) {
            std::cerr << "nclink-agent: cannot write " << *o.acl_path << "\n";
            return 1;
        }
        return 0;
    }
    if (!o.broker && !o.config_path) {
        usage(std::cerr);
        return kExitUsage;
    }

    // Block the signals before any thread starts, so only sigwait() sees them.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    nclink::Logger logger(nclink::stderr_sink(), config.log_level);
    {
        // Every answer through a broker without TCP_NODELAY is 40-90 ms late;
        // the agent cannot change the broker but can say which setting to
        // change (docs/performance.md).
        nclink::MqttOptions probe;
        probe.broker_url = config.broker_url;
        probe.client_id = (config.client_id.empty() ? config.agent_id : config.client_id) + "-" + std::to_string(::getpid());
        probe.username = config.username;
        probe.password = config.password;
        probe.tls = config.tls;
        probe.mqtt_version = config.mqtt_version;
        if (auto trip = nclink::measure_broker_round_trip(probe, 3)) {
            if (const std::string warning = nclink::broker_delay_warning(*trip); !warning.empty())
                logger.warn("nclink-agent: {}", warning);
        } else {
            logger.warn("nclink-agent: broker round trip not measured: {}", trip.error().describe());
        }
    }
    nclink::Agent agent(config, logger);
    // /metrics (docs/metrics.md): bound before the agent starts, so a port
    // that cannot be bound stops the program before it serves anything.
    std::unique_ptr<nclink::http::MetricsEndpoint> metrics;
    if (o.metrics) {
        std::optional<nclink::http::BasicAuth> auth;
        if (o.metrics_user) {
            const char* password = std::getenv("NCLINK_METRICS_PASSWORD");
            auth = nclink::http::BasicAuth{*o.metrics_user, password ? password : "", "nclink-agent", {}};
        }
        auto made = nclink::http::MetricsEndpoint::start(
            *o.metrics, [&agent] { return nclink::prometheus_metrics(agent); }, "nclink_agent", std::move(auth), logger);
        if (!made) {
            logger.error("nclink-agent: --metrics {}: {}", *o.metrics, made.error().describe());
            return 1;
        }
        metrics = std::move(made).value();
        logger.info("nclink-agent: metrics on http://{}:{}/metrics", metrics->host(), metrics->port());
    }
    if (auto started = agent.start(); !started) {
        logger.error("nclink-agent: {}", started.error().describe());
        return 1;
    }
    // A broker that refuses us (credentials, a certificate) will go on
    // refusing: say why and exit. An unreachable one is waited for.
    for (int i = 0; i < 200 && agent.stats().transport.connects == 0; ++i) {
        const auto link = agent.stats().transport;
        if (link.refused) {
            agent.stop();
            std::cerr << "nclink-agent: cannot connect to " << config.broker_url << ": " << link.last_error << "\n";
            return 1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    logger.info("nclink-agent: serving on {} (share group '{}'); SIGHUP reloads, SIGINT/SIGTERM stops",
                config.broker_url, config.share_group);
    int signal_number = 0;
    while (true) {
        sigwait(&signals, &signal_number);
        if (signal_number != SIGHUP) break;
        reload(o, agent, logger);
    }
    logger.info("nclink-agent: {} received, stopping", signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    if (metrics) metrics->stop();
    agent.stop();
    return 0;
}
