// nclink-sim: a simulated machine on NC-Link. Runs an nclink Adapter with the
// simulated driver (any usable model; the 3-axis mill by default) against a
// broker until SIGINT/SIGTERM. SIGHUP re-reads --config: log_level applies at
// once, other changes at the next start (Adapter::reload); a file with a
// problem is refused and the running configuration stays. With --machines or
// --gateway it serves many simulated machines in one process (nclink::Gateway);
// there SIGHUP re-reads the gateway file (or, for --machines, --config) and
// Gateway::reload() touches only the machines it changed. Argument parsing and wiring
// only: everything else is the SDK.
//
//   nclink-sim [--broker URL] [--model FILE] [--guid GUID] [--config FILE]
//              [--plugin SO] [--persistence DIR] [--seed N] [--strict]
//              [--log-level LEVEL] [--metrics HOST:PORT]
//   nclink-sim --machines N [...]    N simulated machines in one gateway process
//   nclink-sim --gateway FILE [...]  the machines a gateway file lists (SIGHUP re-reads it)
#include "http/metrics_endpoint.hpp"
#include "program.hpp"

#include <nclink/adapter.hpp>
#include <nclink/adapter_metrics.hpp>
#include <nclink/gateway.hpp>
#include <nclink/model.hpp>
#include <nclink/model_cache.hpp>
#include "sim/sim_driver.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace {

using nclink::program::kExitCannotRun;
using nclink::program::kExitUsage;
constexpr const char* kProgram = "nclink-sim";

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
  --machines N        simulate N machines in one process (gateway mode, docs/gateway.md): models
                      alternate between the mill and the standard's appendix B machine (or all
                      --model), GUIDs <guid>-0000... (--guid is the prefix, default "sim"),
                      seeds --seed + i; --config gives the settings every machine shares
  --gateway FILE      serve the machines a gateway file lists (docs/gateway.md); SIGHUP re-reads
                      it and adds or removes machines without touching the others
  --metrics HOST:PORT serve the adapter's Prometheus metrics at http://HOST:PORT/metrics
                      (off by default, as in firmware; loopback only; docs/metrics.md);
                      in gateway mode every machine's, labelled by its terminal id
  --help)";

struct Options {
    nclink::AdapterConfig config;
    std::string config_file;
    std::uint64_t seed = 1;
    std::size_t machines = 0;
    std::string gateway_file;
    bool model_given = false, broker_given = false, guid_given = false, strict_given = false, persistence_given = false,
         plugin_given = false, level_given = false;
    std::string model, broker, guid, plugin, persistence, metrics;
    nclink::LogLevel level = nclink::LogLevel::info;
};

[[noreturn]] void usage_error(const std::string& message) {
    std::fprintf(stderr, "nclink-sim: %s\n%s\n", message.c_str(), kUsage);
    std::exit(kExitUsage);
}

Options parse(int argc, char** argv) {
    Options o;
    for (nclink::program::Arguments args(argc, argv); args.next();) {
        const std::string arg = args.current();
        auto value = [&]() -> std::string {
            std::string text;
            if (!args.value(text)) usage_error(arg + " needs a value");
            return text;
        };
        if (args.help()) {
            std::printf("%s\n", kUsage);
            std::exit(nclink::program::kExitOk);
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
        } else if (arg == "--machines") {
            o.machines = std::strtoull(value().c_str(), nullptr, 10);
            if (o.machines == 0) usage_error("--machines needs a positive number");
        } else if (arg == "--gateway") {
            o.gateway_file = value();
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

std::string default_model(const char* name = "sim-mill.json");

// The linked simulator for a machine: its model file, its seed. The model
// comes through `models`, so the simulators of one file share the parsed
// model as the gateway's adapters do (nclink/model_cache.hpp).
nclink::Result<std::shared_ptr<nclink::Driver>> sim_driver(nclink::ModelCache& models, const nclink::MachineConfig& machine) {
    const auto loaded = models.load(machine.adapter.model_path);
    if (!loaded.model)
        return nclink::make_error(nclink::ErrorCode::syntax_error, machine.adapter.model_path + " cannot be simulated");
    nclink::SimOptions sim;
    const auto& dc = machine.adapter.driver_config;
    if (dc.is_object() && dc.contains("seed") && dc["seed"].is_number_unsigned()) sim.seed = dc["seed"].get<std::uint64_t>();
    sim.device = machine.adapter.device_id;
    auto created = nclink::SimDriver::create(loaded.model, sim);
    if (!created) return std::move(created).error();
    return std::shared_ptr<nclink::Driver>(std::move(created).value());
}

// The machines of gateway mode: those the gateway file lists, or N
// simulated ones made from the shared configuration (alternating models,
// one seed each). The same at start and at every SIGHUP.
nclink::Result<nclink::GatewayConfig> gateway_machines(const Options& o, const nclink::AdapterConfig& shared) {
    if (!o.gateway_file.empty()) return nclink::load_gateway_config(o.gateway_file);
    nclink::GatewayConfig gateway;
    const std::string prefix = o.guid_given ? o.guid : "sim";
    const std::string models[] = {default_model("sim-mill.json"), default_model("appendix-b-corrected.json")};
    for (std::size_t i = 0; i < o.machines; ++i) {
        nclink::MachineConfig m;
        m.adapter = shared;
        m.adapter.model_path = o.model_given ? o.model : models[i % 2];
        m.adapter.dev_uuid = fmt::format("{}-{:04d}", prefix, i);
        m.adapter.device_id.clear();
        m.adapter.driver_config = nclink::Json{{"seed", o.seed + i}};
        if (!m.adapter.driver_plugin.empty()) m.adapter.driver_config["model"] = m.adapter.model_path;
        m.id = m.adapter.dev_uuid;
        gateway.machines.push_back(std::move(m));
    }
    return gateway;
}

nclink::Result<nclink::AdapterConfig> effective_config(const Options& o);

// SIGHUP in gateway mode: the gateway file (or --config, for --machines) is
// read again and Gateway::reload() serves what it now says; a file with a
// problem is refused and every machine keeps running as it was.
void reload_gateway(const Options& o, nclink::Gateway& gw, const nclink::Logger& logger) {
    const std::string file = o.gateway_file.empty() ? o.config_file : o.gateway_file;
    if (file.empty()) return nclink::program::log_nothing_to_reload(logger, kProgram, "--gateway or --config file");
    auto shared = effective_config(o);
    auto next = shared ? gateway_machines(o, *shared) : nclink::Result<nclink::GatewayConfig>(shared.error());
    if (!next) {
        logger.error("nclink-sim: {} not re-read, the machines keep running as they were: {}", file, next.error().message);
        return;
    }
    const nclink::GatewayReload r = gw.reload(std::move(next).value());
    using nclink::program::joined;
    logger.info("nclink-sim: {} re-read: {} machine(s) serving; added [{}], removed [{}], restarted [{}], applied in place [{}]",
                file, gw.machines().size(), joined(r.added), joined(r.removed), joined(r.restarted), joined(r.applied));
    for (const auto& e : r.errors) logger.error("nclink-sim: {}", e);
}

// Gateway mode: many simulated machines in this process until a signal.
int run_gateway(const Options& o, const nclink::AdapterConfig& shared, const nclink::program::Signals& signals,
                const nclink::Logger& logger) {
    auto machines = gateway_machines(o, shared);
    if (!machines) return nclink::program::fail(kProgram, machines.error().message, kExitUsage);
    const nclink::GatewayConfig gateway = std::move(machines).value();
    nclink::ModelCache models;
    nclink::Gateway gw(
        gateway, [&models](const nclink::MachineConfig& m) { return sim_driver(models, m); }, logger);
    if (auto started = gw.start(); !started) logger.warn("nclink-sim: {}", started.error().message);
    logger.info("nclink-sim: {} machine(s) serving (Ctrl-C to stop)", gw.machines().size());
    // One exposition of the machines serving at the moment of the scrape
    // (the HTTP server's thread; Gateway calls are thread-safe).
    std::unique_ptr<nclink::http::MetricsEndpoint> metrics;
    if (!o.metrics.empty()) {
        auto scrape = [&gw] {
            std::vector<std::shared_ptr<nclink::Adapter>> held;
            for (const auto& m : gw.machines())
                if (auto adapter = gw.machine(m.id)) held.push_back(std::move(adapter));
            std::vector<const nclink::Adapter*> adapters;
            for (const auto& a : held) adapters.push_back(a.get());
            return nclink::prometheus_metrics(adapters);
        };
        // The HTTP limits of --config's "metrics" section (the machines' own are not read: one endpoint).
        auto made = nclink::http::MetricsEndpoint::start(o.metrics, scrape, "nclink_adapter", std::nullopt, logger, shared.metrics);
        if (!made) {
            logger.error("nclink-sim: --metrics {}: {}", o.metrics, made.error().describe());
            gw.stop();
            return kExitCannotRun;
        }
        metrics = std::move(made).value();
        logger.info("nclink-sim: metrics on http://{}:{}/metrics", metrics->host(), metrics->port());
    }
    signals.serve([&] { reload_gateway(o, gw, logger); });
    if (metrics) metrics->stop();
    gw.stop();
    return nclink::program::kExitOk;
}

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

void reload(const Options& o, nclink::Adapter& adapter, const nclink::Logger& logger) {
    if (o.config_file.empty()) return nclink::program::log_nothing_to_reload(logger, kProgram);
    auto next = effective_config(o);
    if (!next) return nclink::program::log_reload_refused(logger, kProgram, next.error().message);
    nclink::program::log_reload(logger, kProgram, o.config_file, adapter.reload(*next));
}

std::string default_model(const char* name) {
    // Installed first (bin/../share/nclink/models), so a packaged program
    // never reads the tree it was built from; the source tree for a build.
    std::vector<std::filesystem::path> dirs;
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(self.parent_path() / NCLINK_BIN_TO_MODELS);
    dirs.emplace_back(NCLINK_SOURCE_MODELS_DIR);
    for (const auto& dir : dirs) {
        const auto path = (dir / name).lexically_normal();
        if (std::filesystem::exists(path, ec)) return path.string();
    }
    return name;
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    // A configuration with a problem stops here, before anything starts:
    // one line naming the file, line and column.
    auto effective = effective_config(o);
    if (!effective) return nclink::program::fail(kProgram, effective.error().message, kExitUsage);
    const nclink::AdapterConfig config = std::move(effective).value();
    const nclink::Logger logger(nclink::stderr_sink(), config.log_level);

    const nclink::program::Signals signals;  // before any thread starts
    if (o.machines > 0 || !o.gateway_file.empty()) return run_gateway(o, config, signals, logger);

    std::shared_ptr<nclink::Driver> driver;
    if (config.driver_plugin.empty()) {
        // The linked simulator simulates the configured model file.
        const auto loaded = nclink::load_model_file(config.model_path);
        if (!loaded.model) {
            return nclink::program::fail(
                kProgram, config.model_path + " cannot be simulated (run `nclink validate " + config.model_path + "`)",
                kExitCannotRun);
        }
        nclink::SimOptions sim;
        sim.seed = o.seed;
        sim.device = config.device_id;
        auto created = nclink::SimDriver::create(loaded.model, sim);
        if (!created) return nclink::program::fail(kProgram, created.error().describe(), kExitCannotRun);
        driver = std::move(created).value();
    }

    nclink::Adapter adapter(config, driver, logger);
    logger.info("nclink-sim: simulating {} on {}", config.model_path, config.broker_url);
    if (auto started = adapter.start(); !started) {
        logger.error("nclink-sim: {}", started.error().message);
        return kExitCannotRun;
    }
    // An unreachable broker is waited for (the adapter buffers meanwhile).
    if (auto why = nclink::program::refused_by_broker([&adapter] { return adapter.stats().transport; })) {
        adapter.stop(std::chrono::milliseconds(0));
        return nclink::program::fail(kProgram, "cannot connect to " + config.broker_url + ": " + *why, kExitCannotRun);
    }
    logger.info("nclink-sim: answering as {} (Ctrl-C to stop)", adapter.dev_uuid());
    std::unique_ptr<nclink::http::MetricsEndpoint> metrics;
    if (!o.metrics.empty()) {
        auto made = nclink::http::MetricsEndpoint::start(
            o.metrics, [&adapter] { return nclink::prometheus_metrics(adapter); }, "nclink_adapter", std::nullopt, logger,
            config.metrics);
        if (!made) {
            logger.error("nclink-sim: --metrics {}: {}", o.metrics, made.error().describe());
            adapter.stop();
            return kExitCannotRun;
        }
        metrics = std::move(made).value();
        logger.info("nclink-sim: metrics on http://{}:{}/metrics", metrics->host(), metrics->port());
    }

    const int stop_signal = signals.serve([&] { reload(o, adapter, logger); });
    logger.info("nclink-sim: {} received, stopping", nclink::program::Signals::name(stop_signal));
    if (metrics) metrics->stop();
    adapter.stop();
    const auto stats = adapter.stats();
    logger.info("nclink-sim: answered {} request(s); {} ignored as repeats, {} retained ignored, {} malformed", stats.requests,
                stats.ignored_duplicates, stats.ignored_retained, stats.rejected);
    return nclink::program::kExitOk;
}
