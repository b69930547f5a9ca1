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
int run_model(const Args& args);  // cmd_model.cpp
extern const char* const model_usage;
int run_vocabulary(const Args& args);  // cmd_model.cpp
extern const char* const vocabulary_usage;

}  // namespace nclink::cli
