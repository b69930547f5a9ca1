#include "config_check.hpp"

#include "core/json_locate.hpp"

#include <algorithm>
#include <set>
#include <tuple>

namespace nclink::cli {
namespace {

std::set<std::string> schema_keys(const ConfigKind& kind) {
    std::set<std::string> keys;
    const auto schema = config_schema(kind.name);
    if (!schema || !schema->contains("properties") || !(*schema)["properties"].is_object()) return keys;
    for (const auto& [key, _] : (*schema)["properties"].items()) keys.insert(key);
    return keys;
}

// Removes the member `pointer` names (for an entry of a list, such as one of
// broker.failover: the whole list); false when it names no object member.
bool set_aside(Json& document, const std::string& pointer) {
    if (pointer.empty()) return false;
    const auto slash = pointer.rfind('/');
    try {
        const Json::json_pointer parent(pointer.substr(0, slash));
        Json& container = document.at(parent);
        if (container.is_array()) return set_aside(document, pointer.substr(0, slash));
        if (!container.is_object()) return false;
        const std::string key = Json::json_pointer(pointer).back();
        return container.erase(key) == 1;
    } catch (const Json::exception&) {
        return false;
    }
}

std::string without_prefix(std::string message) {
    static const std::string prefix = "configuration: ";
    if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
    return message;
}

}  // namespace

const ConfigKind* guess_config_kind(const Json& document, std::string& why) {
    why.clear();
    if (!document.is_object()) {
        why = "the file does not hold a JSON object";
        return nullptr;
    }
    struct Score {
        const ConfigKind* kind;
        std::size_t known = 0, unknown = 0;
    };
    std::vector<Score> scores;
    for (const auto& kind : config_kinds()) {
        const auto keys = schema_keys(kind);
        Score s{&kind};
        for (const auto& [key, _] : document.items()) (keys.count(key) ? s.known : s.unknown)++;
        scores.push_back(s);
    }
    std::vector<const Score*> complete;
    for (const auto& s : scores)
        if (s.unknown == 0) complete.push_back(&s);
    std::string names;
    for (const auto& kind : config_kinds()) names += std::string(names.empty() ? "" : ", ") + kind.name;
    if (complete.size() == 1) return complete.front()->kind;
    if (complete.size() > 1) {
        why = "its keys are valid in several kinds (" + names + "); give --kind";
        return nullptr;
    }
    const Score* best = nullptr;
    bool tie = false;
    for (const auto& s : scores) {
        if (!best || s.known > best->known) {
            best = &s;
            tie = false;
        } else if (s.known == best->known) {
            tie = true;
        }
    }
    if (!best || best->known == 0 || tie) {
        why = "its keys belong to no one kind (" + names + "); give --kind";
        return nullptr;
    }
    return best->kind;
}

ConfigCheck check_config_text(std::string_view text, const ConfigKind* kind) {
    ConfigCheck out;
    Json document;
    try {
        document = Json::parse(text);
    } catch (const Json::parse_error& e) {
        const auto at = core_detail::position_of_offset(text, e.byte == 0 ? 0 : e.byte - 1);
        std::string what = e.what();
        if (const auto colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
        out.problems.push_back(ConfigProblem{"", at.line, at.column, ErrorCode::syntax_error, "not valid JSON: " + what});
        out.kind = kind;
        return out;
    }
    if (!kind) {
        kind = guess_config_kind(document, out.undecided);
        out.kind_guessed = kind != nullptr;
        if (!kind) {
            if (!document.is_object())  // a problem of the file whatever its kind
                out.problems.push_back(ConfigProblem{"", 1, 1, ErrorCode::syntax_error, "the file must hold a JSON object"});
            return out;
        }
    }
    out.kind = kind;
    // The readers stop at the first problem: set it aside and read again, so
    // one run lists them all. Bounded by the number of keys in the file.
    for (int round = 0; round < 1000; ++round) {
        auto checked = kind->check(document);
        if (checked) break;
        const Error& e = checked.error();
        ConfigProblem p{e.pointer, 0, 0, e.code, without_prefix(e.message)};
        if (const auto at = core_detail::locate_pointer(text, e.pointer); at && (!e.pointer.empty() || !document.is_object())) {
            p.line = at->line;
            p.column = at->column;
        }
        out.problems.push_back(std::move(p));
        if (!set_aside(document, e.pointer)) break;
    }
    // In the order of the file; problems without a place last.
    std::stable_sort(out.problems.begin(), out.problems.end(), [](const ConfigProblem& a, const ConfigProblem& b) {
        return std::make_tuple(a.line == 0, a.line, a.column) < std::make_tuple(b.line == 0, b.line, b.column);
    });
    return out;
}

}  // namespace nclink::cli
