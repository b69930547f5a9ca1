// `nclink events --device GUID ID [--key K|--index N] [--filter F]...
// [--trigger T] [--count N]`: registers an event (Register/Event) and prints
// its Event DTUs as they come; unregisters it on the way out.
#include "cli_device.hpp"
#include "cli_inbox.hpp"
#include "event_args.hpp"

#include <unistd.h>

#include <cstdio>

namespace nclink::cli {

const char* const events_usage =
    "usage: nclink events --device GUID [options] ID\n"
    "       nclink events [options] GUID ID\n"
    "  Registers an event on data item ID and prints each event as it comes:\n"
    "    TIME EVENT_ID ITEM[KEY|INDEX] OLD -> NEW\n"
    "  until Ctrl-C, N events (--count), or the first event of --trigger once.\n"
    "  The event is unregistered on the way out.\n"
    "options:\n"
    "  --key K           watch the dict element K (dict items need it)\n"
    "  --index N         watch the list element N (list items need it)\n"
    "  --filter F        a filter; repeat for several (OR-ed, in order). F is JSON\n"
    "                    (an object or an array of them) or a short form:\n"
    "                      change[:VARIANCE]  equal:VALUE  range:FROM,TO[,VARIANCE]\n"
    "                      less:VALUE[,VARIANCE]  greater:VALUE[,VARIANCE]  include:V1,V2,...\n"
    "                    none: the adapter's default change filter\n"
    "  --trigger T       always (default), normal or once\n"
    "  --count N         stop after N events\n"
    "  --json            one Event DTU per line\n"
    "    nclink events --device mill spindle_speed --filter greater:8000 --trigger normal\n"
    "    nclink events --device mill parameters --key P100 --filter "
    "'{\"type\":\"change\",\"variance\":5}'\n" NCLINK_CLI_GLOBAL_OPTIONS;

namespace {

// --filter may repeat, which CliOptions (one value per option) cannot hold:
// take every --filter out of the arguments first.
Args take_filters(const Args& args, std::vector<Json>& filters) {
    Args rest;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg == "--") {
            rest.insert(rest.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
            break;
        }
        if (arg == "--filter") {
            if (i + 1 >= args.size()) throw UsageError{"--filter needs a value"};
            for (auto& f : parse_filter_arg(args[++i])) filters.push_back(std::move(f));
        } else if (arg.rfind("--filter=", 0) == 0) {
            for (auto& f : parse_filter_arg(arg.substr(9))) filters.push_back(std::move(f));
        } else {
            rest.push_back(arg);
        }
    }
    return rest;
}

}  // namespace

int run_events(const Args& all_args) {
    std::vector<Json> filters;
    const Args args = take_filters(all_args, filters);
    CliOptions options = parse_cli_options(args, {{}, {"--key", "--index", "--trigger", "--count"}});
    if (options.help) {
        std::fputs(events_usage, stdout);
        return 0;
    }
    // `nclink events GUID ID` as well as `--device GUID ID`.
    if (options.device.empty() && options.positionals.size() == 2) {
        options.device = options.positionals.front();
        options.positionals.erase(options.positionals.begin());
    }
    check_terminal_id("--device", options.device);
    if (options.client_id.empty()) options.client_id = "nclink-cli-" + std::to_string(::getpid());
    check_terminal_id("--client-id", options.client_id);
    if (options.positionals.size() != 1) throw UsageError{options.positionals.empty() ? "no ID given" : "give one ID"};

    Client::EventRegistration registration;
    registration.id = options.positionals.front();
    registration.filters = std::move(filters);
    if (const auto it = options.values.find("--key"); it != options.values.end()) registration.key = it->second;
    if (const auto it = options.values.find("--index"); it != options.values.end())
        registration.index = static_cast<std::int64_t>(parse_count("--index", it->second, true));
    if (registration.key && registration.index) throw UsageError{"give --key or --index, not both"};
    if (const auto it = options.values.find("--trigger"); it != options.values.end()) {
        if (it->second != "always" && it->second != "normal" && it->second != "once")
            throw UsageError{"--trigger must be always, normal or once"};
        registration.trigger = it->second;
    }
    std::uint64_t count = 0;
    if (const auto it = options.values.find("--count"); it != options.values.end()) count = parse_count("--count", it->second);
    if (registration.trigger == "once") count = 1;  // the adapter releases it after one event

    install_interrupt_handler();
    // Before the client: its dispatch thread pushes into the inbox until the
    // client is destroyed, so the inbox must outlive it.
    Inbox<EventData> inbox;
    auto client = connect_client(options);
    auto event_id = client->register_event(options.device, std::move(registration), [&](const EventData& e) { inbox.push(e); });
    if (!event_id) {
        std::fprintf(stderr, "nclink events: %s\n", event_id.error().describe().c_str());
        return 1;
    }
    if (!options.json) {
        std::fprintf(stderr, "event %s registered; waiting for events (Ctrl-C ends)\n", event_id->c_str());
    }
    std::uint64_t seen = 0;
    while (count == 0 || seen < count) {
        auto dtu = inbox.pop(std::chrono::steady_clock::time_point::max());
        if (!dtu) break;  // Ctrl-C
        ++seen;
        if (options.json) std::printf("%s\n", encode(*dtu).c_str());
        else std::printf("%s %s\n", format_time_ms(dtu->time).c_str(), format_event(*dtu).c_str());
        std::fflush(stdout);
    }
    if (client->event_registrations() > 0) {
        if (auto gone = client->unregister_event(options.device, *event_id); !gone)
            std::fprintf(stderr, "nclink events: unregistering %s: %s\n", event_id->c_str(), gone.error().describe().c_str());
    }
    return 0;
}

}  // namespace nclink::cli
