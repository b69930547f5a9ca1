// `nclink validate [--strict] FILE...`: every problem of every file as
// `file:pointer: severity: message`, then one summary line per file.
// Exit 1 on any fatal or conformance problem (and on warnings with --strict).
#include "commands.hpp"

#include <nclink/model.hpp>

#include <cstdio>

namespace nclink::cli {

const char* const validate_usage =
    "usage: nclink validate [--strict] FILE...\n"
    "  Checks NC-Link model (probe) files. Prints each problem as\n"
    "  FILE:POINTER: SEVERITY: MESSAGE and a summary line per file.\n"
    "  Exit status: 0 when no file has fatal or conformance problems,\n"
    "  1 otherwise, 2 on usage errors.\n"
    "  --strict  also fail on warnings\n";

int run_validate(const Args& args) {
    bool strict = false;
    std::vector<std::string> files;
    bool options_done = false;
    for (const auto& arg : args) {
        if (!options_done && (arg == "--help" || arg == "-h")) {
            std::fputs(validate_usage, stdout);
            return 0;
        }
        if (!options_done && arg == "--strict") {
            strict = true;
        } else if (!options_done && arg == "--") {
            options_done = true;
        } else if (!options_done && arg.size() > 1 && arg[0] == '-') {
            throw UsageError{"unknown option " + arg};
        } else {
            files.push_back(arg);
        }
    }
    if (files.empty()) throw UsageError{"no FILE given"};

    bool failed = false;
    for (const auto& file : files) {
        const LoadResult result = load_model_file(file);
        for (const auto& p : result.problems)
            std::printf("%s:%s: %s: %s\n", file.c_str(), p.pointer.empty() ? "/" : p.pointer.c_str(),
                        std::string(to_string(p.severity)).c_str(), p.message.c_str());
        const std::size_t fatal = result.count(Severity::fatal);
        const std::size_t conformance = result.count(Severity::conformance);
        const std::size_t warnings = result.count(Severity::warning);
        std::printf("%s: %zu fatal, %zu conformance, %zu warning%s\n", file.c_str(), fatal, conformance, warnings,
                    warnings == 1 ? "" : "s");
        if (fatal > 0 || conformance > 0 || (strict && warnings > 0)) failed = true;
    }
    return failed ? 1 : 0;
}

}  // namespace nclink::cli
