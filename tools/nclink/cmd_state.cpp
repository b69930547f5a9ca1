// `nclink state --device GUID [--follow] [--count N]`: the device's
// Notify/State (retained, so the current state arrives at once): online or
// offline. --follow keeps printing changes until Ctrl-C.
#include "cli_device.hpp"
#include "cli_inbox.hpp"

#include <cstdio>

namespace nclink::cli {

const char* const state_usage =
    "usage: nclink state --device GUID [--follow] [--count N] [options]\n"
    "  Prints the device's state from Notify/State/GUID (online/offline).\n"
    "  Without --follow: the current (retained) state; exit 1 when none arrives\n"
    "  within the timeout. --follow: every change until Ctrl-C (or N states).\n" NCLINK_CLI_GLOBAL_OPTIONS;

int run_state(const Args& args) {
    CliOptions options;
    if (parse_device_command(args, {{"--follow"}, {"--count"}}, state_usage, options)) return 0;
    if (!options.positionals.empty()) throw UsageError{"unexpected argument " + options.positionals.front()};
    const bool follow = options.flags.count("--follow") > 0;
    std::uint64_t count = follow ? 0 : 1;
    if (const auto it = options.values.find("--count"); it != options.values.end()) count = parse_count("--count", it->second);

    install_interrupt_handler();
    // Before the client: its dispatch thread pushes into the inbox until the
    // client is destroyed, so the inbox must outlive it.
    Inbox<NotifyState> inbox;
    auto client = connect_client(options);
    if (auto sub = client->subscribe_state(options.device, [&](const NotifyState& s) { inbox.push(s); }); !sub) {
        std::fprintf(stderr, "nclink state: %s\n", sub.error().describe().c_str());
        return 1;
    }
    const auto first_deadline = std::chrono::steady_clock::now() + options.timeout;
    std::uint64_t seen = 0;
    while (count == 0 || seen < count) {
        auto state = inbox.pop(seen == 0 && !follow ? first_deadline : std::chrono::steady_clock::time_point::max());
        if (!state) break;
        ++seen;
        const std::string tid = state->tid.empty() ? options.device : state->tid;
        const std::string value = state->state.empty() ? "unknown" : state->state;
        if (options.json) std::printf("%s\n", Json{{"tid", tid}, {"state", value}}.dump().c_str());
        else std::printf("%s: %s\n", tid.c_str(), value.c_str());
        std::fflush(stdout);
    }
    if (seen == 0 && !interrupted()) {
        std::fprintf(stderr, "nclink state: no state published for %s\n", options.device.c_str());
        return 1;
    }
    return 0;
}

}  // namespace nclink::cli
