// `nclink model new`: writes a starter model (include/nclink/starter_model.hpp)
// for a lathe, a machining center or a generic machine, and validates it
// before writing. `nclink vocabulary`: prints docs/vocabulary.md.
#include "commands.hpp"

#include <nclink/model.hpp>
#include <nclink/starter_model.hpp>
#include <nclink/vocabulary.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace nclink::cli {

const char* const model_usage =
    "usage: nclink model new --kind lathe|machining-center|generic [options]\n"
    "  Writes a starter model (probe file) and validates it (docs/porting-guide.md).\n"
    "  --kind KIND       lathe (axes X Z), machining-center (X Y Z) or generic (none)\n"
    "  --id ID           device id (default: the kind); the guid is ID-0001\n"
    "  --name TEXT       device name\n"
    "  --manufacturer T  machine builder (default ACME)\n"
    "  --axes LIST       axis numbers of table 9, comma-separated (X,Z or X,Y,Z,C)\n"
    "  --spindles N      spindles, each an AXIS numbered S (S1, S2...)\n"
    "  --channels N      CNC channels, one CONTROLLER each (0: no CNC)\n"
    "  -o FILE           write here (default: standard output)\n";

const char* const vocabulary_usage =
    "usage: nclink vocabulary\n"
    "  Prints the chapter 7 vocabulary the validator knows, as Markdown (docs/vocabulary.md).\n";

namespace {

int parse_count(const std::string& option, const std::string& text) {
    char* end = nullptr;
    const long n = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || n < 0 || n > 9) throw UsageError{option + " needs a number from 0 to 9"};
    return static_cast<int>(n);
}

}  // namespace

int run_model(const Args& args) {
    if (args.empty()) throw UsageError{"no subcommand (new)"};
    if (args[0] == "--help" || args[0] == "-h") {
        std::fputs(model_usage, stdout);
        return 0;
    }
    if (args[0] != "new") throw UsageError{"unknown subcommand " + args[0]};
    StarterModelOptions o;
    bool kind_given = false, id_given = false;
    std::string out;
    for (std::size_t i = 1; i < args.size(); ++i) {
        const std::string& arg = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError{arg + " needs a value"};
            return args[++i];
        };
        if (arg == "--help" || arg == "-h") {
            std::fputs(model_usage, stdout);
            return 0;
        } else if (arg == "--kind") {
            auto kind = machine_kind_from_string(value());
            if (!kind) throw UsageError{kind.error().message};
            o.kind = *kind, kind_given = true;
        } else if (arg == "--id") {
            o.id = value(), id_given = true;
        } else if (arg == "--name") {
            o.name = value();
        } else if (arg == "--manufacturer") {
            o.manufacturer = value();
        } else if (arg == "--axes") {
            std::stringstream list(value());
            for (std::string axis; std::getline(list, axis, ',');)
                if (!axis.empty()) o.axes.push_back(axis);
        } else if (arg == "--spindles") {
            o.spindles = parse_count(arg, value());
        } else if (arg == "--channels") {
            o.channels = parse_count(arg, value());
        } else if (arg == "-o" || arg == "--output") {
            out = value();
        } else {
            throw UsageError{"unknown option " + arg};
        }
    }
    if (!kind_given) throw UsageError{"--kind is required"};
    if (!id_given) o.id = o.kind == MachineKind::lathe ? "lathe" : o.kind == MachineKind::machining_center ? "mc" : "machine";
    auto model = make_starter_model(o);
    if (!model) throw UsageError{model.error().message};
    // Validated on creation: a starter model the SDK would refuse is a bug.
    const LoadResult checked = parse_model(model->dump());
    bool clean = checked.ok();
    for (const auto& p : checked.problems) {
        std::fprintf(stderr, "nclink model new: %s: %s: %s\n", p.pointer.c_str(), std::string(to_string(p.severity)).c_str(),
                     p.message.c_str());
        clean = false;
    }
    if (!clean) return 1;
    // Written back by the SDK: chapter 6's attribute order (id, name, type...).
    const std::string text = serialize_model(*checked.model);
    if (out.empty()) {
        std::fputs(text.c_str(), stdout);
        return 0;
    }
    std::ofstream file(out, std::ios::binary);
    file << text;
    if (!file.flush()) {
        std::fprintf(stderr, "nclink model new: cannot write %s\n", out.c_str());
        return 1;
    }
    std::fprintf(stderr, "nclink model new: wrote %s (valid, no problems)\n", out.c_str());
    return 0;
}

int run_vocabulary(const Args& args) {
    if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
        std::fputs(vocabulary_usage, stdout);
        return 0;
    }
    if (!args.empty()) throw UsageError{"no arguments expected"};
    std::fputs(vocabulary_markdown().c_str(), stdout);
    return 0;
}

}  // namespace nclink::cli
