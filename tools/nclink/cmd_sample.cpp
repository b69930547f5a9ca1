// `nclink sample [--device] DEV ID... --sample-ms N --upload-ms N`: registers a
// dynamic sample channel (Register/Sample, 8.2.17) and prints its rows live,
// one line per row (time and one column per id); unregisters on Ctrl-C or
// after --count rows.
#include "cli_device.hpp"
#include "commands.hpp"
#include "cli_inbox.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace nclink::cli {

int run_sample(const Args& args);  // main.cpp dispatches here
const char* const sample_usage =
    "usage: nclink sample [options] DEV ID... --sample-ms N --upload-ms N\n"
    "       nclink sample --device DEV [options] ID... --sample-ms N --upload-ms N\n"
    "  Registers a dynamic sample channel (Register/Sample) reading the data\n"
    "  items ID... every --sample-ms and publishing every --upload-ms (>= the\n"
    "  sample interval), then prints its rows live: the row's time and one\n"
    "  column per ID. A row the adapter replayed after an outage of its broker\n"
    "  link is flagged with '*'. Ctrl-C (or --count rows) unregisters the channel.\n"
    "  --count N         stop after N rows\n"
    "  --qos 0|1         QoS of the channel's Sample DTUs (default: the adapter's sampling.qos, 1)\n"
    "  --keepalive-ms N  send a small Query every N ms so the adapter keeps the\n"
    "                    channel (its application lease; default 60000, 0 = never)\n"
    "  --json            one Sample DTU per line, as received\n" NCLINK_CLI_GLOBAL_OPTIONS;

namespace {

std::string cell(const Json& value) {
    return value.is_null() ? "null" : value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

void print_rows(const SampleDtu& dtu, double sample_ms, std::uint64_t& printed, std::uint64_t limit) {
    std::size_t rows = 0;
    for (const auto& column : dtu.data) rows = std::max(rows, column.is_array() ? column.size() : std::size_t{1});
    const bool replayed = Client::is_replayed(dtu);
    for (std::size_t r = 0; r < rows && (limit == 0 || printed < limit); ++r, ++printed) {
        const auto t = dtu.begin_time + static_cast<std::int64_t>(static_cast<double>(r) * sample_ms);
        std::printf("%s%s", format_time_ms(t).c_str(), replayed ? "*" : " ");
        for (const auto& column : dtu.data) {
            const Json& value = column.is_array() ? (r < column.size() ? column[r] : Json()) : column;
            std::printf(" %14s", cell(value).c_str());
        }
        std::printf("\n");
    }
    std::fflush(stdout);
}

}  // namespace

int run_sample(const Args& args) {
    CliOptions options;
    const OptionSpec spec{{}, {"--sample-ms", "--upload-ms", "--count", "--qos", "--keepalive-ms"}};
    options = parse_cli_options(args, spec);
    if (options.help) {
        std::fputs(sample_usage, stdout);
        return 0;
    }
    if (options.device.empty()) {  // DEV first, like call/control
        if (options.positionals.empty()) throw UsageError{"no device given (DEV or --device)"};
        options.device = options.positionals.front();
        options.positionals.erase(options.positionals.begin());
    }
    check_terminal_id("--device", options.device);
    if (options.client_id.empty()) options.client_id = "nclink-cli-" + std::to_string(::getpid());
    check_terminal_id("--client-id", options.client_id);
    if (options.positionals.empty()) throw UsageError{"no data item ids given"};
    for (const auto& id : options.positionals)
        if (id.empty()) throw UsageError{"empty data item id"};
    auto value_of = [&](const char* name) -> std::optional<std::uint64_t> {
        const auto it = options.values.find(name);
        if (it == options.values.end()) return std::nullopt;
        return parse_count(name, it->second, std::string_view(name) == "--keepalive-ms" || std::string_view(name) == "--qos");
    };
    const auto sample_ms = value_of("--sample-ms");
    const auto upload_ms = value_of("--upload-ms");
    if (!sample_ms || !upload_ms) throw UsageError{"--sample-ms and --upload-ms are required"};
    const std::uint64_t count = value_of("--count").value_or(0);
    const auto qos = value_of("--qos");
    if (qos && *qos > 1) throw UsageError{"--qos must be 0 or 1"};
    const auto keepalive = std::chrono::milliseconds(value_of("--keepalive-ms").value_or(60000));

    install_interrupt_handler();
    Inbox<SampleDtu> inbox;  // outlives the client (its dispatch thread pushes)
    auto client = connect_client(options);
    RequestOptions request;
    if (qos) request.private_info = Json{{"qos", *qos}};
    auto channel = client->register_sampling(
        options.device, options.positionals, std::chrono::milliseconds(*sample_ms), std::chrono::milliseconds(*upload_ms),
        [&](const SampleDtu& dtu) { inbox.push(dtu); }, request);
    if (!channel) {
        std::fprintf(stderr, "nclink sample: %s\n", channel.error().describe().c_str());
        return 1;
    }
    std::fprintf(stderr, "nclink sample: channel %s on Sample/%s/%s/%s (Ctrl-C stops)\n", channel->id.c_str(),
                 options.device.c_str(), client->ex_cid().c_str(), channel->id.c_str());
    if (!options.json) {
        std::printf("%-25s", "time");
        for (const auto& id : options.positionals) std::printf(" %14s", id.c_str());
        std::printf("\n");
    }
    std::uint64_t printed = 0;
    auto next_keepalive = std::chrono::steady_clock::now() + keepalive;
    while (count == 0 || printed < count) {
        auto wait_until = keepalive.count() > 0 ? next_keepalive : std::chrono::steady_clock::time_point::max();
        auto dtu = inbox.pop(wait_until);
        if (interrupted()) break;
        if (keepalive.count() > 0 && std::chrono::steady_clock::now() >= next_keepalive) {
            // Any DTU renews the application lease (8.2.18.3); a Query of one
            // sampled item is the cheapest that is always valid.
            client->query_async(options.device, {QueryItem{options.positionals.front(), std::nullopt}},
                                [](Result<std::vector<QueryResult>>) {});
            next_keepalive = std::chrono::steady_clock::now() + keepalive;
        }
        if (!dtu) continue;
        if (options.json) {
            std::printf("%s\n", encode(*dtu).c_str());
            std::fflush(stdout);
            printed += dtu->data.empty() || !dtu->data[0].is_array() ? 1 : dtu->data[0].size();
        } else {
            print_rows(*dtu, static_cast<double>(*sample_ms), printed, count);
        }
    }
    if (auto gone = client->unregister_sampling(*channel); !gone) {
        std::fprintf(stderr, "nclink sample: unregister %s: %s\n", channel->id.c_str(), gone.error().describe().c_str());
        return 1;
    }
    return 0;
}

}  // namespace nclink::cli
