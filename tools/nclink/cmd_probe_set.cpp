// `nclink probe-set --device GUID FILE`: replaces the device's model with the
// model file FILE (Probe/Set, 8.2.9/8.2.10). The file is checked locally
// first (as `nclink validate` does), so an unusable model is not sent; the
// adapter checks it again and may refuse it (its reason is printed).
#include "cli_device.hpp"

#include <nclink/model.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace nclink::cli {

const char* const probe_set_usage =
    "usage: nclink probe-set --device GUID FILE [--force] [options]\n"
    "  Sends the model file FILE to the device (Probe/Set) and prints the answer.\n"
    "  FILE is validated first; fatal problems stop it unless --force is given.\n"
    "  The adapter announces the new version (Probe/Version) once it took it.\n"
    NCLINK_CLI_GLOBAL_OPTIONS;

int run_probe_set(const Args& args) {
    CliOptions options;
    if (parse_device_command(args, {{"--force"}}, probe_set_usage, options)) return 0;
    if (options.positionals.size() != 1) throw UsageError{"one model FILE expected"};
    const std::string path = options.positionals.front();
    std::ifstream in(path);
    if (!in) {
        std::fprintf(stderr, "nclink probe-set: cannot read %s\n", path.c_str());
        return 1;
    }
    std::stringstream text;
    text << in.rdbuf();
    const LoadResult loaded = parse_model(text.str());
    bool fatal = !loaded.model;
    for (const auto& p : loaded.problems) {
        if (p.severity == Severity::fatal) fatal = true;
        if (p.severity != Severity::warning)
            std::fprintf(stderr, "%s:%s: %s: %s\n", path.c_str(), p.pointer.empty() ? "/" : p.pointer.c_str(),
                         std::string(to_string(p.severity)).c_str(), p.message.c_str());
    }
    if (fatal && options.flags.count("--force") == 0) {
        std::fprintf(stderr, "nclink probe-set: %s is not a usable model (--force sends it anyway)\n", path.c_str());
        return 1;
    }
    const Json model = Json::parse(text.str(), nullptr, false);
    if (model.is_discarded()) {
        std::fprintf(stderr, "nclink probe-set: %s is not JSON\n", path.c_str());
        return 1;
    }
    auto client = connect_client(options);
    auto set = client->probe_set(options.device, model);
    if (!set) {
        std::fprintf(stderr, "nclink probe-set: %s refused it: %s\n", options.device.c_str(),
                     set.error().describe().c_str());
        return 1;
    }
    std::printf("%s: model replaced\n", options.device.c_str());
    return 0;
}

}  // namespace nclink::cli
