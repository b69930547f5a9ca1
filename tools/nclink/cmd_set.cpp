// `nclink set --device GUID ID=VALUE... | ID:{params}...`: one Set request;
// prints `id: OK` or `id: NG ...` per item.
#include "cli_device.hpp"

#include "client_args.hpp"

#include <cstdio>

namespace nclink::cli {

const char* const set_usage =
    "usage: nclink set --device GUID [options] ID=VALUE... | ID:PARAMS...\n"
    "  Sets data items. VALUE is JSON if it parses, else a string; PARAMS is the\n"
    "  full params object (value/values, index/indexes, key/keys, offset, ...):\n"
    "    nclink set --device mill feed_override=80 'tools:{\"index\":2,\"value\":{\"length\":10}}'\n"
    "  Prints `ID: OK` or `ID: NG ERROR REASON` per item (--json: the results).\n"
    "  Exit status 1 when any item is NG or the request fails.\n" NCLINK_CLI_GLOBAL_OPTIONS;

int run_set(const Args& args) {
    CliOptions options;
    if (parse_device_command(args, {}, set_usage, options)) return 0;
    if (options.positionals.empty()) throw UsageError{"no ID=VALUE given"};
    std::vector<SetItem> items;
    for (const auto& spec : options.positionals) {
        auto item = parse_set_spec(spec);
        if (!item) throw UsageError{item.error().message};
        items.push_back(std::move(item).value());
    }
    auto client = connect_client(options);
    auto results = client->set(options.device, std::move(items));
    if (!results) {
        std::fprintf(stderr, "nclink set: %s\n", results.error().describe().c_str());
        return 1;
    }
    bool all_ok = true;
    Json out = Json::array();
    for (const auto& r : *results) {
        all_ok = all_ok && r.status.ok;
        if (options.json) {
            Json item{{"id", r.id}, {"code", r.status.code()}};
            if (r.params) item["params"] = *r.params;
            if (r.status.reason) item["reason"] = *r.status.reason;
            if (r.status.error) item["error"] = *r.status.error;
            out.push_back(std::move(item));
        } else {
            std::printf("%s\n", format_set_result(r).c_str());
        }
    }
    if (options.json) std::printf("%s\n", out.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
    return all_ok ? 0 : 1;
}

}  // namespace nclink::cli
