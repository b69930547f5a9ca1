#include "conform/cli_options.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>

namespace nclink::conform {

const char* const usage_text =
    "usage: nclink-conform --broker URL --device GUID [options]\n"
    "\n"
    "Runs the test items of GB/T 41970-2022 tables 55-62 against one adapter and\n"
    "writes the test record of table C.1.\n"
    "\n"
    "  --broker URL        MQTT broker the adapter is on (tcp://host:1883, ssl://...)\n"
    "  --device GUID       the adapter's terminal id (its model GUID)\n"
    "  --client-id ID      the tester's terminal id (default nclink-conform-<random>)\n"
    "  --username U        broker user name; --password P its password\n"
    "  --report FILE.md    write the record as Markdown (default: stdout)\n"
    "  --json FILE         write the record as JSON\n"
    "  --allow-write       run the items that change the machine (Set, Probe/Set,\n"
    "                      methods); every change is undone. Without it they are skipped.\n"
    "  --method ID         the method to call in the method items (with --allow-write);\n"
    "                      pick one that is harmless on this machine\n"
    "  --method-args JSON  its args (default: the args the model declares)\n"
    "  --timeout-ms N      wait for one answer (default 3000)\n"
    "  --max-wait-ms N     longest wait for a run of samples (default 30000)\n"
    "  --verbose           progress on stderr\n"
    "\n"
    "Exit status: 0 pass, 1 fail, 2 usage or connection error.\n";

namespace {

Result<long long> number(const std::string& option, const std::string& text) {
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || v <= 0)
        return make_error(ErrorCode::value_type, fmt::format("{} wants a positive number, not \"{}\"", option, text));
    return v;
}

}  // namespace

Result<CliOptions> parse_cli(const std::vector<std::string>& args) {
    CliOptions o;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--help" || a == "-h") {
            o.help = true;
            return o;
        }
        if (a == "--allow-write") {
            o.run.allow_write = true;
            continue;
        }
        if (a == "--verbose" || a == "-v") {
            o.verbose = true;
            continue;
        }
        const bool takes_value = a == "--broker" || a == "--device" || a == "--client-id" || a == "--report" || a == "--json" ||
                                 a == "--timeout-ms" || a == "--max-wait-ms" || a == "--method" || a == "--method-args" ||
                                 a == "--username" || a == "--password";
        if (!takes_value) return make_error(ErrorCode::keys_of_arguments, fmt::format("unknown option \"{}\"", a));
        if (i + 1 >= args.size()) return make_error(ErrorCode::parameter_missing, fmt::format("{} needs a value", a));
        const std::string& v = args[++i];
        if (a == "--broker") o.broker = v;
        else if (a == "--device") o.run.device = v;
        else if (a == "--client-id") o.client_id = v;
        else if (a == "--report") o.report_md = v;
        else if (a == "--json") o.report_json = v;
        else if (a == "--method") o.run.method = v;
        else if (a == "--username") o.username = v;
        else if (a == "--password") o.password = v;
        else if (a == "--method-args") {
            Json parsed = Json::parse(v, nullptr, false);
            if (parsed.is_discarded()) return make_error(ErrorCode::value_type, "--method-args is not JSON");
            o.run.method_args = parsed;
        } else {
            auto n = number(a, v);
            if (!n) return n.error();
            (a == "--timeout-ms" ? o.run.timeout : o.run.max_wait) = std::chrono::milliseconds(n.value());
        }
    }
    if (o.broker.empty()) return make_error(ErrorCode::parameter_missing, "--broker is required");
    if (o.run.device.empty()) return make_error(ErrorCode::parameter_missing, "--device is required");
    if (o.client_id.find_first_of("+#/") != std::string::npos || o.run.device.find_first_of("+#/") != std::string::npos)
        return make_error(ErrorCode::unsupported_terminal_id,
                          "terminal ids cannot contain '+', '#' or '/' (they are topic levels)");
    o.run.broker = o.broker;
    return o;
}

}  // namespace nclink::conform
