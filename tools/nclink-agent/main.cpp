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
#include "program.hpp"

#include <nclink/agent.hpp>
#include <nclink/agent_metrics.hpp>
#include <nclink/log.hpp>
#include <nclink/mqtt_transport.hpp>

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <unistd.h>
#include <string>

namespace {

using nclink::program::kExitCannotRun;
using nclink::program::kExitUsage;
constexpr const char* kProgram = "nclink-agent";

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

void reload(const Options& o, nclink::Agent& agent, const nclink::Logger& logger) {
    if (!o.config_path) return nclink::program::log_nothing_to_reload(logger, kProgram);
    auto next = effective_config(o);
    if (!next) return nclink::program::log_reload_refused(logger, kProgram, next.error().message);
    auto report = agent.reload(*next);
    if (!report) return nclink::program::log_reload_refused(logger, kProgram, report.error().describe());
    nclink::program::log_reload(logger, kProgram, *o.config_path, *report);
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (nclink::program::Arguments args(argc, argv); args.next();) {
        bool ok = true;
        if (args.is("--broker")) ok = args.value(o.broker);
        else if (args.is("--config")) ok = args.value(o.config_path);
        else if (args.is("--state-dir")) ok = args.value(o.state_dir);
        else if (args.is("--log-level")) ok = args.value(o.log_level);
        else if (args.is("--write-mosquitto-acl")) ok = args.value(o.acl_path);
        else if (args.is("--metrics")) ok = args.value(o.metrics);
        else if (args.is("--metrics-user")) ok = args.value(o.metrics_user);
        else if (args.is("--check-config")) o.check_only = true;
        else if (args.help()) {
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
    if (o.log_level && !nclink::log_level_from_string(*o.log_level))
        return nclink::program::fail(kProgram, "unknown log level " + *o.log_level, kExitUsage);
    if (o.check_only && !o.config_path) return nclink::program::fail(kProgram, "--check-config needs --config FILE", kExitUsage);

    // A configuration with a problem stops here, before anything is started
    // or written: one line naming the file, line and column.
    auto loaded = effective_config(o);
    if (!loaded) return nclink::program::fail(kProgram, loaded.error().message, kExitUsage);
    nclink::AgentConfig config = std::move(loaded).value();
    if (o.check_only) {
        std::cout << *o.config_path << ": OK\n";
        return 0;
    }

    if (o.acl_path) {
        std::ofstream out(*o.acl_path);
        out << nclink::mosquitto_acl(config);
        if (!out.good()) return nclink::program::fail(kProgram, "cannot write " + *o.acl_path, kExitCannotRun);
        return nclink::program::kExitOk;
    }
    if (!o.broker && !o.config_path) {
        usage(std::cerr);
        return kExitUsage;
    }

    const nclink::program::Signals signals;  // before any thread starts

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
            *o.metrics, [&agent] { return nclink::prometheus_metrics(agent); }, "nclink_agent", std::move(auth), logger,
            config.metrics);
        if (!made) {
            logger.error("nclink-agent: --metrics {}: {}", *o.metrics, made.error().describe());
            return kExitCannotRun;
        }
        metrics = std::move(made).value();
        logger.info("nclink-agent: metrics on http://{}:{}/metrics", metrics->host(), metrics->port());
    }
    if (auto started = agent.start(); !started) {
        logger.error("nclink-agent: {}", started.error().describe());
        return kExitCannotRun;
    }
    if (auto why = nclink::program::refused_by_broker([&agent] { return agent.stats().transport; })) {
        agent.stop();
        return nclink::program::fail(kProgram, "cannot connect to " + config.broker_url + ": " + *why, kExitCannotRun);
    }
    const std::string sharing =
        config.instances > 1 ? fmt::format("instance {} of {}, plain subscriptions", config.instance, config.instances)
        : agent.share_group_in_use().empty() ? std::string("plain subscriptions: the broker has no $share")
                                             : fmt::format("share group '{}'", agent.share_group_in_use());
    logger.info("nclink-agent: serving on {} ({}); SIGHUP reloads, SIGINT/SIGTERM stops", config.broker_url, sharing);
    const int stop_signal = signals.serve([&] { reload(o, agent, logger); });
    logger.info("nclink-agent: {} received, stopping", nclink::program::Signals::name(stop_signal));
    if (metrics) metrics->stop();
    agent.stop();
    return nclink::program::kExitOk;
}
