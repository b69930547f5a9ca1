// `nclink`: the command-line companion of the SDK. main() only dispatches;
// every subcommand is a file of its own (validate.cpp, ...).
#include "cli_device.hpp"
#include "commands.hpp"

#include <nclink/version.hpp>

#include <cstdio>
#include <exception>
#include <string_view>

namespace {

using nclink::cli::Command;

const Command kCommands[] = {
    {"validate", "check model (probe) files against GB/T 41970-2022 chapters 6 and 7", &nclink::cli::run_validate,
     nclink::cli::validate_usage},
    {"config", "check a configuration file (adapter, agent) or print its JSON Schema", &nclink::cli::run_config,
     nclink::cli::config_usage},
    {"map", "write a model as MTConnect Devices or OPC UA NodeSet2 XML (GB/T 39561.3)", &nclink::cli::run_map,
     nclink::cli::map_usage},
    {"discovery", "list the adapters the agent knows (Discovery)", &nclink::cli::run_discovery, nclink::cli::discovery_usage},
    {"model", "model new: write a starter model for a lathe, machining center or generic machine", &nclink::cli::run_model,
     nclink::cli::model_usage},
    {"vocabulary", "print the chapter 7 types and units the validator knows (Markdown)", &nclink::cli::run_vocabulary,
     nclink::cli::vocabulary_usage},
    {"probe", "print a device's model (Probe/Query) as a tree", &nclink::cli::run_probe, nclink::cli::probe_usage},
    {"probe-set", "replace the model of one or many devices with a model file (Probe/Set), with progress",
     &nclink::cli::run_probe_set, nclink::cli::probe_set_usage},
    {"query", "query data items: ID[:PARAMS]...", &nclink::cli::run_query, nclink::cli::query_usage},
    {"set", "set data items: ID=VALUE... or ID:PARAMS...", &nclink::cli::run_set, nclink::cli::set_usage},
    {"watch", "print a device's samples as a rolling table", &nclink::cli::run_watch, nclink::cli::watch_usage},
    {"top", "a device's live values, full screen (watch --full-screen)", &nclink::cli::run_top, nclink::cli::watch_usage},
    {"events", "register an event on a data item: DEV ID, print its events live", &nclink::cli::run_events,
     nclink::cli::events_usage},
    {"sample", "register a dynamic sample channel: DEV ID..., print its rows", &nclink::cli::run_sample, nclink::cli::sample_usage},
    {"state", "print a device's online/offline state", &nclink::cli::run_state, nclink::cli::state_usage},
    {"call", "call a method: DEV METHOD [ARGS_JSON], with progress", &nclink::cli::run_call, nclink::cli::call_usage},
    {"control", "stop, resume or cancel a running method", &nclink::cli::run_control, nclink::cli::control_usage},
    {"stats", "print an adapter's statistics (sample channels, link)", &nclink::cli::run_stats, nclink::cli::stats_usage},
};

void print_usage(std::FILE* out) {
    std::fprintf(out, "usage: nclink <command> [options]\n\ncommands:\n");
    for (const auto& c : kCommands) std::fprintf(out, "  %-10s %s\n", c.name, c.summary);
    std::fprintf(out, "\n`nclink <command> --help` describes a command.\n");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        print_usage(stderr);
        return 2;
    }
    const std::string_view name = argv[1];
    if (name == "--help" || name == "-h" || name == "help") {
        print_usage(stdout);
        return 0;
    }
    if (name == "--version") {
        std::printf("nclink %s\n", nclink::library_version());
        return 0;
    }
    for (const auto& c : kCommands) {
        if (name != c.name) continue;
        const nclink::cli::Args args(argv + 2, argv + argc);
        try {
            return c.run(args);
        } catch (const nclink::cli::UsageError& e) {
            std::fprintf(stderr, "nclink %s: %s\n%s", c.name, e.message.c_str(), c.usage);
            return 2;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "nclink %s: %s\n", c.name, e.what());
            return 1;
        }
    }
    std::fprintf(stderr, "nclink: unknown command \"%s\"\n", argv[1]);
    print_usage(stderr);
    return 2;
}
