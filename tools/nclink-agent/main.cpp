// nclink-agent: runs the NC-Link agent beside an MQTT broker (docs/agent.md).
// Argument parsing and wiring only; the agent lives in src/agent/.
//
//   nclink-agent --broker URL [--config FILE] [--state-dir DIR] [--log-level L]
//   nclink-agent [--config FILE] --write-mosquitto-acl FILE
#include <nclink/log.hpp>
#include <nclink/agent.hpp>
#include <nclink/mqtt_transport.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <pthread.h>
#include <unistd.h>
#include <string>
#include <thread>

namespace {

void usage(std::ostream& out) {
    out << "usage: nclink-agent --broker URL [--config FILE] [--state-dir DIR] [--log-level LEVEL]\n"
           "       nclink-agent [--config FILE] --write-mosquitto-acl FILE\n"
           "Runs the NC-Link agent (registration, discovery, state, version cache,\n"
           "DEV_UNREACHABLE/timeouts, access control) until SIGINT/SIGTERM.\n"
           "--write-mosquitto-acl writes a mosquitto acl_file enforcing the configured\n"
           "access rules and exits. See docs/agent.md.\n";
}

}  // namespace

int main(int argc, char** argv) {
    std::optional<std::string> broker, config_path, state_dir, log_level, acl_path;
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
        else if (arg == "--state-dir") ok = value(state_dir);
        else if (arg == "--log-level") ok = value(log_level);
        else if (arg == "--write-mosquitto-acl") ok = value(acl_path);
        else if (arg == "-h" || arg == "--help") {
            usage(std::cout);
            return 0;
        } else {
            std::cerr << "nclink-agent: unknown argument " << arg << "\n";
            ok = false;
        }
        if (!ok) {
            usage(std::cerr);
            return 2;
        }
    }

    nclink::AgentConfig config;
    if (config_path) {
        auto loaded = nclink::load_agent_config(*config_path);
        if (!loaded) {
            std::cerr << "nclink-agent: " << loaded.error().describe() << "\n";
            return 1;
        }
        config = std::move(loaded).value();
    }
    if (broker) config.broker_url = *broker;
    if (state_dir) config.state_dir = *state_dir;
    if (log_level) {
        auto level = nclink::log_level_from_string(*log_level);
        if (!level) {
            std::cerr << "nclink-agent: unknown log level " << *log_level << "\n";
            return 2;
        }
        config.log_level = *level;
    }

    if (acl_path) {
        std::ofstream out(*acl_path);
        out << nclink::mosquitto_acl(config);
        if (!out.good()) {
            std::cerr << "nclink-agent: cannot write " << *acl_path << "\n";
            return 1;
        }
        return 0;
    }
    if (!broker && !config_path) {
        usage(std::cerr);
        return 2;
    }

    // Block the signals before any thread starts, so only sigwait() sees them.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
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
    logger.info("nclink-agent: serving on {} (share group '{}'); SIGINT/SIGTERM stops", config.broker_url,
                config.share_group);
    int signal_number = 0;
    sigwait(&signals, &signal_number);
    logger.info("nclink-agent: {} received, stopping", signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    agent.stop();
    return 0;
}
