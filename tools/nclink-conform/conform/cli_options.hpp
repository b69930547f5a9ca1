// Command line of nclink-conform, parsed without side effects (testable).
#pragma once

#include "conform/runner.hpp"

#include <nclink/result.hpp>

#include <string>
#include <vector>

namespace nclink::conform {

struct CliOptions {
    RunOptions run;
    std::string broker;       ///< --broker URL (required)
    std::string client_id;    ///< --client-id ("" = nclink-conform-<random>)
    std::string username;     ///< --username
    std::string password;     ///< --password
    std::string report_md;    ///< --report FILE.md ("" and no --json: Markdown on stdout)
    std::string report_json;  ///< --json FILE
    bool help = false;
    bool verbose = false;  ///< --verbose: progress on stderr
};

extern const char* const usage_text;

/// Parses argv[1..]. Fails with parameter_missing (no --broker/--device, an
/// option without its value) or keys_of_arguments (unknown option) or
/// value_type (a number or JSON that does not parse).
Result<CliOptions> parse_cli(const std::vector<std::string>& args);

}  // namespace nclink::conform
