// nclink-sim: a simulated machine on NC-Link. Runs an nclink Adapter with the
// simulated driver (any usable model; the 3-axis mill by default) against a
// broker until SIGINT/SIGTERM. SIGHUP re-reads --config: log_level applies at
// once, other changes at the next start (Adapter::reload); a file with a
// problem is refused and the running configuration stays. Argument parsing
// and wiring only: everything else is the SDK.
//
//   nclink-sim [--broker URL] [--model FILE] [--guid GUID] [--config FILE]
//              [--plugin SO] [--persistence DIR] [--seed N] [--strict]
//              [--log-level LEVEL] [--metrics HOST:PORT]
#include "http/metrics_endpoint.hpp"

#include <nclink/adapter.hpp>
#include <nclink/adapter_metrics.hpp>
#include <nclink/model.hpp>
#include "sim/sim_driver.hpp"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

const char* kUsage = R"(usage: nclink-sim [options]
  --broker URL        MQTT broker (default tcp://127.0.0.1:1883)
  --model FILE        probe (model) file to simulate (default: the 3-axis mill, models/sim-mill.json)
  --guid GUID         terminal id to answer as (default: the device guid, else its id)
  --config FILE       adapter configuration (JSON, see docs/configuration.md); options given here win
  --plugin SO         load the simulator as a driver plugin (e.g. build/lib/nclink-sim.so) instead of the linked one
  --persistence DIR   keep Probe/Set models and settable values here
  --seed N            seed of the simulation (default 1)
  --strict            refuse models with conformance problems
  --log-level LEVEL   trace, debug, info (default), warn, error, off
  --metrics HOST:PORT serve the adapter's Prometheus metrics at http://HOST:PORT/metrics
                      (off by default, as in firmware; loopback only; docs/metrics.md)
  --help)";

struct Options {
    nclink::AdapterConfig config;
    std::string config_file;
    std::uint64_t seed = 1;
    bool model_given = false, broker_given = false, guid_given = false, strict_given = false,
         persistence_given = false, plugin_given = false, level_given = false;
    std::string model, broker, guid, plugin, persistence, metrics;
    nclink::LogLevel level = nclink::LogLevel::info;
};

[[noreturn]] void usage_error(const std::string& message) {
    std::fprintf(stderr, "nclink-sim: %s\n%s\n", message.c_str(), kUsage);
    std::exit(2);
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage_error(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "--help" || arg == "-h") {
            std::printf("%s\n", kUsage);
            std::exit(0);
        } else if (arg == "--broker") {
            o.broker = value(), o.broker_given = true;
        } else if (arg == "--model") {
            o.model = value(), o.model_given = true;
        } else if (arg == "--guid") {
            o.guid = value(), o.guid_given = true;
        } else if (arg == "--config") {
            o.config_file = value();
        } else if (arg == "--plugin") {
            o.plugin = value(), o.plugin_given = true;
        } else if (arg == "--persistence") {
            o.persistence = value(), o.persistence_given = true;
        } else if (arg == "--seed") {
            o.seed = std::strtoull(value().c_str(), nullptr, 10);
        } else if (arg == "--metrics") {
            o.metrics = value();
        } else if (arg == "--strict") {
            o.strict_given = true;
        } else if (arg == "--log-level") {
            auto level = nclink::log_level_from_string(value());
            if (!level) usage_error("unknown log level");
            o.level = *level, o.level_given = true;
        } else {
            usage_error("unknown option " + arg);
        }
    }
    return o;
}

std::string default_model();

// The file's configuration (if any) with the command line's options on top:
// the same at start and at every reload, so a reload sees only what the
// file changed.
nclink::Result<nclink::AdapterConfig> effective_config(const Options& o) {
    nclink::AdapterConfig config;
    if (!o.config_file.empty()) {
        auto loaded = nclink::load_adapter_config(o.config_file);
        if (!loaded) return std::move(loaded).error();
        config = std::move(loaded).value();
    }
    if (o.level_given) config.log_level = o.level;
    if (o.broker_given) config.broker_url = o.broker;
    if (o.model_given) config.model_path = o.model;
    if (config.model_path.empty()) config.model_path = default_model();
    if (o.guid_given) config.dev_uuid = o.guid;
    if (o.strict_given) config.strict = true;
    if (o.persistence_given) config.persistence_dir = o.persistence;
    if (o.plugin_given) {
        config.driver_plugin = o.plugin;
        if (config.driver_config.is_null()) config.driver_config = nclink::Json::object();
        config.driver_config["model"] = config.model_path;
        config.driver_config["seed"] = o.seed;
    }
    return config;
}

std::string joined(const std::vector<std::string>& keys) {
    std::string out;
    for (const auto& k : keys) out += (out.empty() ? "" : ", ") + k;
    return out;
}

void reload(const Options& o, nclink::Adapter& adapter, const nclink::Logger& logger) {
    if (o.config_file.empty()) {
        logger.warn("nclink-sim: SIGHUP: no --config file to reload");
        return;
    }
    auto next = effective_config(o);
    if (!next) {
        logger.error("nclink-sim: reload refused, the running configuration stays: {}", next.error().message);
        return;
    }
    const nclink::ConfigReload report = adapter.reload(*next);
    if (report.applied.empty() && report.restart_needed.empty())
        logger.info("nclink-sim: reloaded {}: nothing changed", o.config_file);
    else if (!report.applied.empty())
        logger.info("nclink-sim: reloaded {}: applied {}", o.config_file, joined(report.applied));
    if (!report.restart_needed.empty())
        logger.warn("nclink-sim: changed in {} but applied only after a restart: {}", o.config_file,
                    joined(report.restart_needed));
}

std::string default_model() {
    // Installed first (bin/../share/nclink/models), so a packaged program
    // never reads the tree it was built from; the source tree for a build.
    std::vector<std::filesystem::path> dirs;
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(self.parent_path() / NCLINK_BIN_TO_MODELS);
    dirs.emplace_back(NCLINK_SOURCE_MODELS_DIR);
    for (const auto& dir : dirs) {
        const auto path = (dir / "sim-mill.json").lexically_normal();
        if (std::filesystem::exists(path, ec)) return path.string();
    }
    return "sim-mill.json";
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    // A configuration with a problem stops here, before anything starts:
    // one line naming the file, line and column.
    auto effective = effective_config(o);
    if (!effective) {
        std::fprintf(stderr, "nclink-sim: %s\n", effective.error().message.c_str());
        return 2;
    }
    const nclink::AdapterConfig config = std::move(effective).value();
    const nclink::Logger logger(nclink::stderr_sink(), config.log_level);

    // Block the signals before any thread starts, so only sigwait() sees them.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    std::shared_ptr<nclink::Driver> driver;
    if (config.driver_plugin.empty()) {
        // The linked simulator simulates the configured model file.
        const auto loaded = nclink::load_model_file(config.model_path);
        if (!loaded.model) {
            std::fprintf(stderr, "nclink-sim: %s cannot be simulated (run `nclink validate %s`)\n",
                         config.model_path.c_str(), config.model_path.c_str());
            return 1;
        }
        nclink::SimOptions sim;
        sim.seed = o.seed;
        sim.device = config.device_id;
        auto created = nclink::SimDriver::create(loaded.model, sim);
        if (!created) {
            std::fprintf(stderr, "nclink-sim: %s\n", created.error().describe().c_str());
            return 1;
        }
        driver = std::move(created).value();
    }

    nclink::Adapter adapter(config, driver, logger);
    logger.info("nclink-sim: simulating {} on {}", config.model_path, config.broker_url);
    if (auto started = adapter.start(); !started) {
        logger.error("nclink-sim: {}", started.error().message);
        return 1;
    }
    logger.info("nclink-sim: answering as {} (Ctrl-C to stop)", adapter.dev_uuid());
    std::unique_ptr<nclink::http::MetricsEndpoint> metrics;
    if (!o.metrics.empty()) {
        auto made = nclink::http::MetricsEndpoint::start(
            o.metrics, [&adapter] { return nclink::prometheus_metrics(adapter); }, "nclink_adapter", std::nullopt, logger);
        if (!made) {
            logger.error("nclink-sim: --metrics {}: {}", o.metrics, made.error().describe());
            adapter.stop();
            return 1;
        }
        metrics = std::move(made).value();
        logger.info("nclink-sim: metrics on http://{}:{}/metrics", metrics->host(), metrics->port());
    }

    int signal_number = 0;
    while (true) {
        sigwait(&signals, &signal_number);
        if (signal_number != SIGHUP) break;
        reload(o, adapter, logger);
    }
    logger.info("nclink-sim: {} received, stopping", signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    if (metrics) metrics->stop();
    adapter.stop();
    const auto stats = adapter.stats();
    logger.info("nclink-sim: answered {} request(s); {} ignored as repeats, {} retained ignored, {} malformed",
                stats.requests, stats.ignored_duplicates, stats.ignored_retained, stats.rejected);
    return 0;
}
