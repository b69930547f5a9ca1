// `nclink stats --device GUID [--item ID]`: the adapter's statistics, read
// with a Query of the SDK-provided data item `nclink_stats`
// (docs/sampling.md). Prints a summary per sample channel; --json the whole
// object.
#include "cli_device.hpp"
#include "commands.hpp"

#include "client_args.hpp"

#include <cstdio>

namespace nclink::cli {

int run_stats(const Args& args);

const char* const stats_usage =
    "usage: nclink stats --device GUID [--item ID] [options]\n"
    "  Prints the adapter's statistics: requests, link, and per sample channel\n"
    "  rows sampled/published, overruns, drops and lateness; every drop by cause\n"
    "  (docs/delivery.md). Read with a Query of\n"
    "  the data item ID (default nclink_stats, see sampling.stats_item).\n"
    "  --json prints the whole statistics object.\n" NCLINK_CLI_GLOBAL_OPTIONS;

namespace {

std::uint64_t num(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it != object.end() && it->is_number() ? it->get<std::uint64_t>() : 0;
}

void print_summary(const Json& stats) {
    std::printf("state: %s, registered: %s, requests: %llu\n", stats.value("state", "?").c_str(),
                stats.value("registered", false) ? "yes" : "no", static_cast<unsigned long long>(num(stats, "requests")));
    if (stats.contains("shed"))  // request intake (docs/security.md, "Bad input and floods")
        std::printf("requests: rejected %llu, shed %llu, oversized %llu, pending %llu\n",
                    static_cast<unsigned long long>(num(stats, "rejected")), static_cast<unsigned long long>(num(stats, "shed")),
                    static_cast<unsigned long long>(num(stats, "oversized")),
                    static_cast<unsigned long long>(num(stats, "pending_requests")));
    if (const auto t = stats.find("transport"); t != stats.end())
        std::printf("transport: published %llu, dropped %llu, buffered %llu\n",
                    static_cast<unsigned long long>(num(*t, "published")), static_cast<unsigned long long>(num(*t, "dropped")),
                    static_cast<unsigned long long>(num(*t, "buffered")));
    if (const auto d = stats.find("drops"); d != stats.end() && d->is_object()) {
        // Every loss by cause (docs/delivery.md, "Counted drops").
        std::string line;
        for (const auto& [cause, count] : d->items())
            line += fmt::format("{}{} {}", line.empty() ? "" : ", ", cause, count.is_number() ? count.get<std::uint64_t>() : 0);
        std::printf("drops: %s\n", line.c_str());
    }
    std::printf("applications released: %llu\n", static_cast<unsigned long long>(num(stats, "applications_released")));
    const Json sampling = stats.value("features", Json::object()).value("sampling", Json::object());
    const Json channels = sampling.value("channels", Json::array());
    if (channels.empty()) {
        std::printf("sampling: no channel running\n");
        return;
    }
    std::printf("%-16s %6s %9s %12s %12s %9s %8s %10s\n", "channel", "mode", "interval", "sampled", "published", "overruns",
                "drops", "max late");
    for (const auto& c : channels) {
        const std::string interval = fmt::format("{}/{}", c.value("sample_interval_ms", 0.0), c.value("upload_interval_ms", 0.0));
        std::printf("%-16s %6s %9s %12llu %12llu %9llu %8llu %8llu us\n", c.value("id", "?").c_str(),
                    c.value("push", false) ? "push" : "pull", interval.c_str(),
                    static_cast<unsigned long long>(num(c, "rows_sampled")),
                    static_cast<unsigned long long>(num(c, "rows_published")), static_cast<unsigned long long>(num(c, "overruns")),
                    static_cast<unsigned long long>(num(c, "drops")), static_cast<unsigned long long>(num(c, "max_lateness_us")));
    }
    if (const auto rt = sampling.find("realtime"); rt != sampling.end() && rt->value("fifo_priority", 0) > 0)
        std::printf("sampling thread SCHED_FIFO %d: %s\n", rt->value("fifo_priority", 0),
                    rt->value("fifo_granted", false) ? "granted" : "refused");
    if (const auto rt = sampling.find("realtime"); rt != sampling.end() && rt->value("slice_us", 0) > 0)
        std::printf("sampling thread time slice %d us: %s\n", rt->value("slice_us", 0),
                    rt->value("slice_granted", false) ? "granted" : "not set (needs Linux >= 6.12)");
}

}  // namespace

int run_stats(const Args& args) {
    CliOptions options;
    if (parse_device_command(args, {{}, {"--item"}}, stats_usage, options)) return 0;
    if (!options.positionals.empty()) throw UsageError{"unexpected argument " + options.positionals.front()};
    std::string item = "nclink_stats";
    if (const auto it = options.values.find("--item"); it != options.values.end()) item = it->second;
    auto client = connect_client(options);
    auto results = client->query(options.device, {QueryItem{item, std::nullopt}});
    if (!results) {
        std::fprintf(stderr, "nclink stats: %s\n", results.error().describe().c_str());
        return 1;
    }
    const QueryResult& r = results->at(0);
    if (!r.status.ok || !r.values || !r.values->is_array() || r.values->empty()) {
        std::fprintf(stderr, "nclink stats: %s\n", format_query_result(r).c_str());
        return 1;
    }
    const Json& stats = (*r.values)[0];
    if (options.json) std::printf("%s\n", stats.dump(2, ' ', false, Json::error_handler_t::replace).c_str());
    else print_summary(stats);
    return 0;
}

}  // namespace nclink::cli
