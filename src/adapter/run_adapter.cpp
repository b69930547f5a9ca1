// run_adapter() (include/nclink/run_adapter.hpp): the adapter program every
// vendor would otherwise copy. Command line and configuration first (exit 2),
// then the model check and start (exit 1), then wait for a signal.
#include <nclink/adapter.hpp>
#include <nclink/model.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/run_adapter.hpp>
#include <nclink/version.hpp>

#include <fmt/format.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <pthread.h>

namespace nclink {
namespace {

const char* kUsage =
    "usage: {0} [options]\n"
    "  --config FILE       adapter configuration (JSON, docs/configuration.md); default {1}\n"
    "  --broker URL        MQTT broker, tcp://HOST[:PORT] (default tcp://127.0.0.1:1883)\n"
    "  --model FILE        model (probe) file\n"
    "  --log-level LEVEL   trace, debug, info (default), warn, error, off\n"
    "  --check             load configuration and model, print what would run, exit\n"
    "  --version           print the nclink version\n"
    "  --help\n";

struct Args {
    std::string config, broker, model, level;
    bool check = false;
};

}  // namespace

int run_adapter(int argc, char** argv, std::shared_ptr<Driver> driver, RunAdapterOptions options) {
    if (options.program.empty())
        options.program = argc > 0 && argv[0] ? std::filesystem::path(argv[0]).filename().string() : "adapter";
    const std::string& program = options.program;
    const std::string usage = fmt::format(
        kUsage, program, options.default_config.empty() ? std::string("none") : options.default_config + " if present");
    auto usage_error = [&](const std::string& message) {
        std::fprintf(stderr, "%s: %s\n%s", program.c_str(), message.c_str(), usage.c_str());
        return 2;
    };

    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool needs_value = arg == "--config" || arg == "--broker" || arg == "--model" || arg == "--log-level";
        if (needs_value && i + 1 >= argc) return usage_error(arg + " needs a value");
        if (arg == "--help" || arg == "-h") {
            std::fputs(usage.c_str(), stdout);
            return 0;
        } else if (arg == "--version") {
            std::printf("%s (nclink %s)\n", program.c_str(), library_version());
            return 0;
        } else if (arg == "--config") {
            a.config = argv[++i];
        } else if (arg == "--broker") {
            a.broker = argv[++i];
        } else if (arg == "--model") {
            a.model = argv[++i];
        } else if (arg == "--log-level") {
            a.level = argv[++i];
        } else if (arg == "--check") {
            a.check = true;
        } else {
            return usage_error("unknown option " + arg);
        }
    }

    AdapterConfig config = options.defaults;
    std::string config_file = a.config;
    if (config_file.empty() && !options.default_config.empty() && std::filesystem::exists(options.default_config))
        config_file = options.default_config;
    if (!config_file.empty()) {
        auto loaded = load_adapter_config(config_file, config);
        if (!loaded) return usage_error(loaded.error().message);
        config = std::move(loaded).value();
    }
    if (!a.broker.empty()) config.broker_url = a.broker;
    if (!a.model.empty()) config.model_path = a.model;
    if (!a.level.empty()) {
        auto level = log_level_from_string(a.level);
        if (!level) return usage_error("unknown log level '" + a.level + "' (trace, debug, info, warn, error, off)");
        config.log_level = *level;
    }
    if (auto usable = check_broker_url(config.broker_url); !usable) return usage_error(usable.error().message);
    if (config.model_path.empty()) return usage_error("no model: give --model FILE or \"model\" in the configuration file");
    if (!driver && config.driver_plugin.empty())
        return usage_error("no driver: this program links none, and the configuration names no driver.plugin");

    const Logger logger(stderr_sink(), config.log_level);
    if (a.check) {
        const LoadResult model = load_model_file(config.model_path);
        for (const auto& p : model.problems)
            std::fprintf(stderr, "%s:%s: %s: %s\n", config.model_path.c_str(), p.pointer.empty() ? "/" : p.pointer.c_str(),
                         std::string(to_string(p.severity)).c_str(), p.message.c_str());
        if (!model.ok()) return 1;
        std::printf("%s: model %s, broker %s, driver %s%s\n", program.c_str(), config.model_path.c_str(),
                    config.broker_url.c_str(), driver ? driver->info().name.c_str() : config.driver_plugin.c_str(),
                    config_file.empty() ? "" : (", configuration " + config_file).c_str());
        return 0;
    }

    // Block the signals before any thread starts, so only sigwait() sees them.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    Adapter adapter(config, driver, logger);
    if (auto started = adapter.start(); !started) {
        logger.error("{}: cannot start: {}", program, started.error().message);
        return 1;
    }
    logger.info("{}: serving {} as {} on {} (Ctrl-C to stop)", program, config.model_path, adapter.dev_uuid(), config.broker_url);
    if (options.on_started) options.on_started(adapter);

    int signal_number = 0;
    sigwait(&signals, &signal_number);
    logger.info("{}: {} received, stopping", program, signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    adapter.stop();
    return 0;
}

}  // namespace nclink
