// `nclink map mtconnect|opcua MODEL.json [--profile basic|cnc] [--device ID]
// [--dev-uuid UUID] [-o FILE]`: the model as an MTConnect 1.4 Devices or an
// OPC UA NodeSet2 document (GB/T 39561.3), on stdout or into FILE. Every
// object that went out under the fallback rule, and every note, is listed on
// stderr. Exit 0 written, 1 model or mapping failed, 2 usage error.
// `nclink map --from-mtconnect PROBE.xml|http://agent [--device D] [-o FILE]`:
// the reverse, an MTConnect device as an NC-Link model (cmd_map_mtconnect.cpp).
#include "commands.hpp"

#include <nclink/mapping.hpp>
#include <nclink/model.hpp>

#include <cstdio>
#include <fstream>
#include <optional>

namespace nclink::cli {

const char* const map_usage =
    "usage: nclink map mtconnect|opcua MODEL.json [options]\n"
    "       nclink map --from-mtconnect PROBE.xml|http://agent:port [--device D] [-o FILE]\n"
    "  Writes the model as an MTConnect 1.4 Devices document (mtconnect) or an\n"
    "  OPC UA NodeSet2 document (opcua), GB/T 39561.3 appendices A and B.\n"
    "  Objects without a standard mapping go out under the fallback rule and\n"
    "  are listed on stderr (docs/mapping.md).\n"
    "  --profile basic|cnc  opcua only: appendix B alone (basic, default) or with\n"
    "                       OPC 40502 CNC objects (cnc; load the CNC nodeset first)\n"
    "  --device ID          map one device (NC-Link id or terminal id); default all\n"
    "  --dev-uuid UUID      terminal id override (one device only)\n"
    "  -o FILE              write to FILE instead of stdout\n"
    "  --from-mtconnect P   the reverse: the NC-Link model of an MTConnect device,\n"
    "                       from a Devices document (a file, or an agent's /probe);\n"
    "                       what has no NC-Link counterpart is listed on stderr;\n"
    "                       --device picks the Device (uuid, name or id)\n"
    "  exit status: 0 written, 1 the model or the mapping failed, 2 usage error\n";

namespace {

struct MapArgs {
    std::string format;
    std::string model;
    std::string output;
    std::optional<std::string> profile;
    std::string from_mtconnect;
    MappingOptions options;
};

MapArgs parse(const Args& args, bool& help) {
    MapArgs out;
    std::vector<std::string> positionals;
    bool options_done = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (options_done || arg.size() < 2 || arg[0] != '-') {
            positionals.push_back(arg);
            continue;
        }
        if (arg == "--") {
            options_done = true;
            continue;
        }
        if (arg == "--help" || arg == "-h") {
            help = true;
            return out;
        }
        std::string name = arg;
        std::optional<std::string> value;
        if (const auto eq = arg.find('='); eq != std::string::npos && arg.rfind("--", 0) == 0) {
            name = arg.substr(0, eq);
            value = arg.substr(eq + 1);
        }
        if (name != "--profile" && name != "--device" && name != "--dev-uuid" && name != "-o" && name != "--output" &&
            name != "--from-mtconnect")
            throw UsageError{"unknown option " + arg};
        if (!value) {
            if (i + 1 >= args.size()) throw UsageError{name + " needs a value"};
            value = args[++i];
        }
        if (value->empty()) throw UsageError{name + " needs a value"};
        if (name == "--profile") out.profile = *value;
        else if (name == "--device") out.options.device = *value;
        else if (name == "--from-mtconnect") out.from_mtconnect = *value;
        else if (name == "--dev-uuid") out.options.dev_uuid = *value;
        else out.output = *value;
    }
    if (!out.from_mtconnect.empty()) {
        if (!positionals.empty()) throw UsageError{"--from-mtconnect takes no format or MODEL.json"};
        if (out.profile || !out.options.dev_uuid.empty()) throw UsageError{"--from-mtconnect takes --device and -o only"};
        return out;
    }
    if (positionals.empty()) throw UsageError{"no format (mtconnect or opcua) given"};
    out.format = positionals[0];
    if (out.format != "mtconnect" && out.format != "opcua")
        throw UsageError{"format must be mtconnect or opcua, not \"" + out.format + "\""};
    if (positionals.size() < 2) throw UsageError{"no MODEL.json given"};
    if (positionals.size() > 2) throw UsageError{"one MODEL.json only"};
    out.model = positionals[1];
    if (out.profile) {
        if (out.format != "opcua") throw UsageError{"--profile applies to opcua only"};
        const auto profile = opcua_profile_from_string(*out.profile);
        if (!profile) throw UsageError{"--profile must be basic or cnc"};
        out.options.opcua_profile = *profile;
    }
    return out;
}

}  // namespace

int run_map(const Args& args) {
    bool help = false;
    const MapArgs a = parse(args, help);
    if (help) {
        std::fputs(map_usage, stdout);
        return 0;
    }
    if (!a.from_mtconnect.empty()) return run_map_from_mtconnect(a.from_mtconnect, a.options.device, a.output);
    const LoadResult loaded = load_model_file(a.model);
    if (!loaded.ok()) {
        for (const auto& p : loaded.problems)
            if (p.severity == Severity::fatal)
                std::fprintf(stderr, "%s:%s: fatal: %s\n", a.model.c_str(), p.pointer.empty() ? "/" : p.pointer.c_str(),
                             p.message.c_str());
        std::fprintf(stderr, "nclink map: %s cannot be loaded\n", a.model.c_str());
        return 1;
    }
    const Result<MappedDocument> doc =
        a.format == "mtconnect" ? map_to_mtconnect(*loaded.model, a.options) : map_to_opcua(*loaded.model, a.options);
    if (!doc) {
        std::fprintf(stderr, "nclink map: %s\n", doc.error().describe().c_str());
        return 1;
    }
    for (const auto& u : doc->unmapped)
        std::fprintf(stderr, "fallback: %s (%s) -> %s: %s\n", u.id.c_str(), u.nclink_type.c_str(), u.fallback.c_str(),
                     u.reason.c_str());
    for (const auto& n : doc->notes) std::fprintf(stderr, "note: %s: %s\n", n.id.c_str(), n.message.c_str());
    if (a.output.empty()) {
        std::fwrite(doc->xml.data(), 1, doc->xml.size(), stdout);
        return std::fflush(stdout) == 0 ? 0 : 1;
    }
    std::ofstream out(a.output, std::ios::binary | std::ios::trunc);
    out.write(doc->xml.data(), static_cast<std::streamsize>(doc->xml.size()));
    out.close();
    if (!out) {
        std::fprintf(stderr, "nclink map: cannot write %s\n", a.output.c_str());
        return 1;
    }
    std::fprintf(stderr, "nclink map: wrote %s (%zu fallback%s)\n", a.output.c_str(), doc->unmapped.size(),
                 doc->unmapped.size() == 1 ? "" : "s");
    return 0;
}

}  // namespace nclink::cli
