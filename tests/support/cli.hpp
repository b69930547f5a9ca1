// Runs the `nclink` command-line tool (built by the nclink_cli target) from an
// integration test and captures its standard output. No Catch assertion in
// here: tests run it on helper threads too, and Catch2 is not thread-safe.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace nclink::test {

struct CliRun {
    int status = -1;  ///< exit status; -1 when it could not run or did not exit
    std::string out;  ///< standard output (standard error is discarded)
};

inline std::string cli_path() { return std::string(NCLINK_BINARY_DIR) + "/bin/nclink"; }

/// False when the tool was not built (NCLINK_BUILD_TOOLS off): tests skip.
inline bool cli_built() { return ::access(cli_path().c_str(), X_OK) == 0; }

inline CliRun run_cli(const std::string& args) {
    CliRun run;
    std::FILE* pipe = ::popen((cli_path() + " " + args + " 2>/dev/null").c_str(), "r");
    if (pipe == nullptr) return run;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.out.append(buffer, n);
    const int status = ::pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
}

/// `nclink COMMAND --broker URL --device DEV REST...` for "COMMAND REST...".
inline CliRun run_cli_on(const std::string& broker_url, const std::string& device, const std::string& args) {
    const auto space = args.find(' ');
    const std::string command = args.substr(0, space);
    const std::string rest = space == std::string::npos ? std::string() : args.substr(space);
    return run_cli(command + " --broker " + broker_url + " --device " + device + rest);
}

}  // namespace nclink::test
