// `nclink discovery`: asks the agent which adapters this application may
// reach (Discovery/Request, 8.2.3) and prints the list of 8.2.4 (guid,
// status, last alive time). Needs an agent: without one nobody answers.
#include "cli_device.hpp"
#include "commands.hpp"

#include <unistd.h>

#include <cstdio>

namespace nclink::cli {

const char* const discovery_usage =
    "usage: nclink discovery [options]\n"
    "  Asks the agent for the adapters this client may reach (Discovery, 8.2.3/8.2.4)\n"
    "  and prints one line per adapter: guid, status, last alive time. Needs an agent\n"
    "  (nclink-agent); exit 1 when none answers within the timeout.\n" NCLINK_CLI_GLOBAL_OPTIONS;

int run_discovery(const Args& args) {
    CliOptions options = parse_cli_options(args);
    if (options.help) {
        std::fputs(discovery_usage, stdout);
        return 0;
    }
    if (!options.positionals.empty()) throw UsageError{"unexpected argument " + options.positionals.front()};
    if (options.client_id.empty()) options.client_id = "nclink-cli-" + std::to_string(::getpid());
    auto client = connect_client(options);
    auto list = client->discover();
    if (!list) {
        std::fprintf(stderr, "nclink discovery: %s\n", list.error().describe().c_str());
        return 1;
    }
    if (options.json) {
        Json out = Json::array();
        for (const auto& d : list.value())
            out.push_back(Json{{"guid", d.guid}, {"status", d.status}, {"lastAliveTimeStamp", d.last_alive_time_stamp}});
        std::printf("%s\n", out.dump().c_str());
        return 0;
    }
    for (const auto& d : list.value()) {
        std::string seen = "-";
        if (!d.last_alive_time_stamp.empty()) {
            try {
                seen = format_time_ms(std::stoll(d.last_alive_time_stamp) * 1000);
            } catch (...) {
                seen = d.last_alive_time_stamp;
            }
        }
        std::printf("%-32s %-8s %s\n", d.guid.c_str(), d.status.c_str(), seen.c_str());
    }
    if (list.value().empty()) std::printf("(no adapter)\n");
    return 0;
}

}  // namespace nclink::cli
