// `nclink config check FILE [--kind KIND] [--json]`: reads a configuration
// file with the program's own reader and prints every problem located by
// line:column and JSON pointer, with the nearest valid key for a typo.
// `nclink config schema [KIND]`: prints a kind's JSON Schema (or lists the
// kinds). docs/configuration.md, "Checking a file".
#include "config_check.hpp"
#include "commands.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace nclink::cli {

const char* const config_usage =
    "usage: nclink config check FILE [--kind KIND] [--json]\n"
    "       nclink config schema [KIND]\n"
    "  check: reads FILE as the program of that kind would and prints every\n"
    "  problem as FILE:LINE:COLUMN: error: KEY: what is wrong (unknown keys with\n"
    "  the nearest valid key). KIND is adapter or agent; without --kind it is\n"
    "  told from the file's keys. --json: one JSON object with every problem.\n"
    "  schema: prints the JSON Schema of KIND (also installed under\n"
    "  /usr/share/nclink/schema/); without KIND, lists the kinds.\n"
    "  Exit status: 0 valid, 1 problems found, 2 usage error, unreadable file,\n"
    "  or a kind that cannot be told from the file.\n";

namespace {

std::string kind_names() {
    std::string names;
    for (const auto& kind : config_kinds()) names += std::string(names.empty() ? "" : ", ") + kind.name;
    return names;
}

const ConfigKind& kind_named(const std::string& name) {
    const ConfigKind* kind = find_config_kind(name);
    if (!kind) throw UsageError{"unknown kind \"" + name + "\" (" + kind_names() + ")"};
    return *kind;
}

int run_check(const Args& args) {
    std::string file, kind_name;
    bool json = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg == "--json") {
            json = true;
        } else if (arg == "--kind" || arg.rfind("--kind=", 0) == 0) {
            if (arg == "--kind") {
                if (i + 1 >= args.size()) throw UsageError{"--kind needs a value"};
                kind_name = args[++i];
            } else {
                kind_name = arg.substr(7);
            }
        } else if (arg.size() > 1 && arg[0] == '-') {
            throw UsageError{"unknown option " + arg};
        } else if (file.empty()) {
            file = arg;
        } else {
            throw UsageError{"one FILE at a time"};
        }
    }
    if (file.empty()) throw UsageError{"no FILE given"};
    const ConfigKind* kind = kind_name.empty() ? nullptr : &kind_named(kind_name);

    std::ifstream in(file, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "nclink config: cannot read %s\n", file.c_str());
        return 2;
    }
    std::stringstream text;
    text << in.rdbuf();
    const ConfigCheck check = check_config_text(text.str(), kind);

    if (json) {
        Json problems = Json::array();
        for (const auto& p : check.problems) {
            Json entry = {{"pointer", p.pointer}, {"code", to_int(p.code)}, {"message", p.message}};
            if (p.line > 0) entry["line"] = p.line, entry["column"] = p.column;
            problems.push_back(std::move(entry));
        }
        Json out = {{"file", file},
                    {"kind", check.kind ? Json(check.kind->name) : Json(nullptr)},
                    {"kind_guessed", check.kind_guessed},
                    {"ok", check.ok()},
                    {"problems", std::move(problems)}};
        if (!check.undecided.empty()) out["undecided"] = check.undecided;
        std::printf("%s\n", out.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
    } else {
        for (const auto& p : check.problems) {
            if (p.line > 0) std::printf("%s:%zu:%zu: error: %s\n", file.c_str(), p.line, p.column, p.message.c_str());
            else std::printf("%s: error: %s\n", file.c_str(), p.message.c_str());
        }
        if (!check.undecided.empty()) {
            std::fprintf(stderr, "nclink config: cannot tell the kind of %s: %s\n", file.c_str(), check.undecided.c_str());
        } else if (check.ok()) {
            std::printf("%s: OK (%s configuration%s)\n", file.c_str(), check.kind->name,
                        check.kind_guessed ? ", told from its keys" : "");
        } else {
            std::printf("%s: %zu problem%s%s\n", file.c_str(), check.problems.size(), check.problems.size() == 1 ? "" : "s",
                        check.kind ? (std::string(" (") + check.kind->name + " configuration)").c_str() : "");
        }
    }
    if (!check.undecided.empty() && check.problems.empty()) return 2;
    return check.ok() ? 0 : 1;
}

int run_schema(const Args& args) {
    if (args.size() > 1) throw UsageError{"one KIND at a time"};
    if (args.empty()) {
        for (const auto& kind : config_kinds()) std::printf("%-10s %s\n", kind.name, kind.summary);
        return 0;
    }
    const ConfigKind& kind = kind_named(args[0]);
    const auto schema = config_schema(kind.name);
    if (!schema) {
        std::fprintf(stderr, "nclink config: no schema is built in for %s\n", kind.name);
        return 1;
    }
    std::printf("%s\n", schema->dump(2, ' ', false, Json::error_handler_t::replace).c_str());
    return 0;
}

}  // namespace

int run_config(const Args& args) {
    if (args.empty()) throw UsageError{"no action given (check, schema)"};
    const std::string& action = args[0];
    if (action == "--help" || action == "-h") {
        std::fputs(config_usage, stdout);
        return 0;
    }
    const Args rest(args.begin() + 1, args.end());
    for (const auto& arg : rest)
        if (arg == "--help" || arg == "-h") {
            std::fputs(config_usage, stdout);
            return 0;
        }
    if (action == "check") return run_check(rest);
    if (action == "schema") return run_schema(rest);
    throw UsageError{"unknown action \"" + action + "\" (check, schema)"};
}

}  // namespace nclink::cli
