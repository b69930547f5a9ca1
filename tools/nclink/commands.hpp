// Subcommands of the `nclink` tool. Each lives in its own file and returns
// the process exit status (0 ok, 1 failure, 2 usage error).
#pragma once

#include <string>
#include <vector>

namespace nclink::cli {

/// Thrown for command-line mistakes; main prints it with the usage and exits 2.
/// (Exceptions are fine here: this is the program's edge, not the SDK.)
struct UsageError {
    std::string message;
};

using Args = std::vector<std::string>;

struct Command {
    const char* name;
    const char* summary;
    int (*run)(const Args& args);  ///< args after the subcommand name
    const char* usage;
};

int run_validate(const Args& args);
extern const char* const validate_usage;
int run_config(const Args& args);  // cmd_config.cpp
extern const char* const config_usage;
int run_map(const Args& args);  // cmd_map.cpp
extern const char* const map_usage;
/// `nclink map --from-mtconnect PROBE` (cmd_map_mtconnect.cpp).
int run_map_from_mtconnect(const std::string& probe, const std::string& device, const std::string& output);
int run_model(const Args& args);  // cmd_model.cpp
extern const char* const model_usage;
int run_vocabulary(const Args& args);  // cmd_model.cpp
extern const char* const vocabulary_usage;
int run_stats(const Args& args);  // cmd_stats.cpp
extern const char* const stats_usage;
int run_sample(const Args& args);  // cmd_sample.cpp
extern const char* const sample_usage;
int run_discovery(const Args& args);  // cmd_discovery.cpp
extern const char* const discovery_usage;
int run_probe_set(const Args& args);  // cmd_probe_set.cpp
extern const char* const probe_set_usage;

}  // namespace nclink::cli
