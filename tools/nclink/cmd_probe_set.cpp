// `nclink probe-set [options] FILE DEV...`: sends one model (Probe/Set,
// 8.2.9/8.2.10) to one or many devices, one after the other, after checking
// it locally (chapters 6-7, as `nclink validate` does), so an unusable model
// is not sent unless --force; each adapter checks it again and may refuse it
// (its reason is printed). Rolling a model out to a line of machines takes a
// while: a progress bar on a terminal, a line per device otherwise.
#include "cli_device.hpp"
#include "commands.hpp"
#include "progress.hpp"

#include <nclink/model.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <future>
#include <sstream>
#include <unistd.h>

namespace nclink::cli {

const char* const probe_set_usage =
    "usage: nclink probe-set [options] FILE DEV...\n"
    "       nclink probe-set --device DEV [options] FILE\n"
    "  Checks the model (probe) FILE like `nclink validate` (fatal problems stop\n"
    "  here unless --force; with --strict conformance problems too), then sends\n"
    "  it to each DEV in turn (Probe/Set) and prints one line per device: OK, or\n"
    "  the NG code and the adapter's reason. An adapter announces the new version\n"
    "  (Probe/Version) once it took the model.\n"
    "  A progress bar on a terminal; plain progress lines otherwise;\n"
    "  --no-progress: only the result lines. --timeout MS applies per device.\n"
    "  Exit status: 0 every device took the model, 1 one did not (or the model\n"
    "  has problems), 2 usage error.\n" NCLINK_CLI_GLOBAL_OPTIONS;

int run_probe_set(const Args& args) {
    CliOptions options = parse_cli_options(args, {{"--no-progress", "--strict", "--force"}, {}});
    if (options.help) {
        std::fputs(probe_set_usage, stdout);
        return 0;
    }
    if (options.positionals.empty()) throw UsageError{"no model FILE given"};
    const std::string file = options.positionals.front();
    std::vector<std::string> devices(options.positionals.begin() + 1, options.positionals.end());
    if (!options.device.empty()) devices.insert(devices.begin(), options.device);
    if (devices.empty()) throw UsageError{"no device given (DEV... or --device)"};
    for (const auto& dev : devices) check_terminal_id("a device", dev);
    if (options.client_id.empty()) options.client_id = "nclink-cli-" + std::to_string(::getpid());
    check_terminal_id("--client-id", options.client_id);

    std::ifstream in(file);
    if (!in) {
        std::fprintf(stderr, "nclink probe-set: cannot read %s\n", file.c_str());
        return 1;
    }
    std::stringstream text;
    text << in.rdbuf();
    const LoadResult loaded = parse_model(text.str());
    const bool strict = options.flags.count("--strict") > 0;
    const bool force = options.flags.count("--force") > 0;
    bool fatal = !loaded.model;
    for (const auto& p : loaded.problems) {
        if (p.severity == Severity::fatal) fatal = true;
        if (p.severity != Severity::warning)
            std::fprintf(stderr, "%s:%s: %s: %s\n", file.c_str(), p.pointer.empty() ? "/" : p.pointer.c_str(),
                         std::string(to_string(p.severity)).c_str(), p.message.c_str());
    }
    if (!force && (fatal || (strict && loaded.count(Severity::conformance) > 0))) {
        std::fprintf(stderr, "nclink probe-set: %s is not sent: it has %s problems (they are above; --force sends it anyway)\n",
                     file.c_str(), fatal ? "fatal" : "conformance");
        return 1;
    }
    const Json model = Json::parse(text.str(), nullptr, false);
    if (model.is_discarded()) {  // even --force cannot send what is not JSON
        std::fprintf(stderr, "nclink probe-set: %s is not JSON\n", file.c_str());
        return 1;
    }

    const ProgressMode mode = progress_mode(options.flags.count("--no-progress") > 0, options.json, stdout);
    install_interrupt_handler();
    auto client = connect_client(options);
    Progress bar(mode, stdout, "probe-set");
    std::size_t failed = 0;
    Json results = Json::array();
    for (std::size_t i = 0; i < devices.size(); ++i) {
        if (interrupted()) break;
        const std::string& dev = devices[i];
        const auto started = std::chrono::steady_clock::now();
        auto promise = std::make_shared<std::promise<Result<void>>>();
        auto future = promise->get_future();
        client->probe_set_async(dev, model, [promise](Result<void> r) { promise->set_value(std::move(r)); });
        const std::string where = dev + " (" + std::to_string(i + 1) + "/" + std::to_string(devices.size()) + ")";
        const double done_before = static_cast<double>(i) / static_cast<double>(devices.size());
        bar.update(done_before, where);
        while (future.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
            char elapsed[32];
            std::snprintf(elapsed, sizeof elapsed, " %.1fs", seconds);
            if (mode == ProgressMode::bar) bar.update(done_before, where + elapsed);
        }
        const Result<void> r = future.get();
        if (!r) ++failed;
        if (options.json)
            results.push_back({{"device", dev}, {"ok", r.ok()}, {"error", r.ok() ? Json(nullptr) : Json(r.error().describe())}});
        else bar.note(dev + ": " + (r.ok() ? std::string("OK") : "NG " + r.error().describe()));
        bar.update(static_cast<double>(i + 1) / static_cast<double>(devices.size()), where);
    }
    bar.finish();
    if (options.json) std::printf("%s\n", results.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
    if (interrupted()) {
        std::fprintf(stderr, "nclink probe-set: interrupted\n");
        return 1;
    }
    return failed == 0 ? 0 : 1;
}

}  // namespace nclink::cli
