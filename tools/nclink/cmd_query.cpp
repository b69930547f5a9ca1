// `nclink query --device GUID ID[:{params}]...`: one Query request with every
// item; prints `id = value` or `id: NG 401 Node not exists` per item.
#include "cli_device.hpp"

#include "client_args.hpp"

#include <cstdio>

namespace nclink::cli {

const char* const query_usage =
    "usage: nclink query --device GUID [options] ID[:PARAMS]...\n"
    "  Queries data items. PARAMS is a JSON object (operation, keys, indexes, ...):\n"
    "    nclink query --device mill x_position 'tools:{\"operation\":\"get_length\"}'\n"
    "  Prints `ID = VALUE` or `ID: NG ERROR REASON` per item (--json: the results).\n"
    "  Exit status 1 when any item is NG or the request fails.\n" NCLINK_CLI_GLOBAL_OPTIONS;

namespace {

Json result_json(const QueryResult& r) {
    Json out{{"id", r.id}, {"code", r.status.code()}};
    if (r.params) out["params"] = *r.params;
    if (r.values) out["values"] = *r.values;
    if (r.status.reason) out["reason"] = *r.status.reason;
    if (r.status.error) out["error"] = *r.status.error;
    return out;
}

}  // namespace

int run_query(const Args& args) {
    CliOptions options;
    if (parse_device_command(args, {}, query_usage, options)) return 0;
    if (options.positionals.empty()) throw UsageError{"no ID given"};
    std::vector<QueryItem> items;
    for (const auto& spec : options.positionals) {
        auto item = parse_query_spec(spec);
        if (!item) throw UsageError{item.error().message};
        items.push_back(std::move(item).value());
    }
    auto client = connect_client(options);
    auto results = client->query(options.device, std::move(items));
    if (!results) {
        std::fprintf(stderr, "nclink query: %s\n", results.error().describe().c_str());
        return 1;
    }
    bool all_ok = true;
    Json out = Json::array();
    for (const auto& r : *results) {
        all_ok = all_ok && r.status.ok;
        if (options.json) out.push_back(result_json(r));
        else std::printf("%s\n", format_query_result(r).c_str());
    }
    if (options.json) std::printf("%s\n", out.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
    return all_ok ? 0 : 1;
}

}  // namespace nclink::cli
