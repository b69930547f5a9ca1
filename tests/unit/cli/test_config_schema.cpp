// The JSON Schemas of docs/schema/ cannot drift from the programs' readers:
// every key a schema lists is accepted by the reader and every key the reader
// accepts is in the schema (the reader lists its valid keys when it refuses an
// unknown one); the defaults the schema states are read; the reload class
// (x-nclink-reload) of every key is what Adapter::reload, Agent::reload and
// Bridge::reload do; and the program carries the same schemas as the
// repository.
#include "config_kinds.hpp"

#include <nclink/adapter.hpp>
#include <nclink/agent.hpp>
#include <nclink/testing/loopback_transport.hpp>

#include "bridge/bridge.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

using namespace nclink;
using namespace nclink::cli;

namespace {

const std::filesystem::path kSchemaDir = NCLINK_SCHEMA_DIR;

Json read_json(const std::filesystem::path& path) {
    std::ifstream in(path);
    return Json::parse(in);
}

std::string pointer_append(std::string pointer, const std::string& key) {
    pointer += '/';
    for (char c : key) pointer += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
    return pointer;
}

bool is_section(const Json& s) { return s.contains("properties"); }
bool is_map(const Json& s) { return s.contains("additionalProperties") && s["additionalProperties"].is_object(); }

// A value the schema allows that differs from its default.
Json changed_value(const Json& s) {
    const Json d = s.value("default", Json());
    if (s.contains("examples")) return s["examples"][0];
    if (s.contains("enum"))
        for (const auto& v : s["enum"])
            if (v != d) return v;
    const std::string type = s.value("type", "");
    if (type == "boolean") return !d.get<bool>();
    if (type == "integer") {
        const long long v = d.is_number() ? d.get<long long>() + 1 : 1;
        return s.contains("maximum") && v > s["maximum"].get<long long>() ? v - 2 : v;
    }
    if (type == "number") return d.is_number() && d.get<double>() != 0 ? d.get<double>() * 2 : 1.5;
    if (type == "string") return "x-test";
    if (type == "object") return Json::object();
    return Json{{"changed", true}};  // free-form ("driver.config")
}

// The default the schema states (or, without one, a valid value).
Json default_value(const Json& s) { return s.contains("default") ? s["default"] : changed_value(s); }

// A whole document: every section present, every leaf from `leaf`; a map
// whose members are sections gets one member "m1".
Json document(const Json& s, const std::function<Json(const Json&)>& leaf) {
    if (is_section(s)) {
        Json out = Json::object();
        for (const auto& [key, child] : s["properties"].items()) out[key] = document(child, leaf);
        return out;
    }
    if (is_map(s) && is_section(s["additionalProperties"])) return Json{{"m1", document(s["additionalProperties"], leaf)}};
    return leaf(s);
}

// Every object node of the schema with its pointer in document(): sections
// (closed: additionalProperties false) and maps (open).
void for_each_object(const Json& s, const std::string& pointer, const std::function<void(const Json&, const std::string&)>& f) {
    if (is_section(s)) {
        f(s, pointer);
        for (const auto& [key, child] : s["properties"].items()) for_each_object(child, pointer_append(pointer, key), f);
    } else if (is_map(s)) {
        f(s, pointer);
        if (is_section(s["additionalProperties"])) for_each_object(s["additionalProperties"], pointer + "/m1", f);
    }
}

// Every leaf of the schema (maps and free-form values count as leaves) with
// its dotted path and the reload class it inherits.
struct Leaf {
    std::string path;
    std::string pointer;
    Json schema;
    std::string reload;
};
void for_each_leaf(const Json& s, const std::string& path, const std::string& pointer, std::string reload, std::vector<Leaf>& out) {
    reload = s.value("x-nclink-reload", reload);
    if (!is_section(s)) {
        out.push_back(Leaf{path, pointer, s, reload});
        return;
    }
    for (const auto& [key, child] : s["properties"].items())
        for_each_leaf(child, path.empty() ? key : path + "." + key, pointer_append(pointer, key), reload, out);
}

std::set<std::string> valid_keys_in(const std::string& message) {
    const std::string marker = "(valid keys: ";
    std::set<std::string> keys;
    const auto start = message.find(marker);
    if (start == std::string::npos) return keys;
    const auto end = message.find(')', start);
    std::string list = message.substr(start + marker.size(), end - start - marker.size());
    std::size_t at = 0;
    while (at <= list.size()) {
        const auto comma = list.find(", ", at);
        keys.insert(list.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
        if (comma == std::string::npos) break;
        at = comma + 2;
    }
    return keys;
}

// What the running program does with `next` when it runs on `running`.
using Reload = std::function<ConfigReload(const Json& running, const Json& next)>;

ConfigReload adapter_reload(const Json& running, const Json& next) {
    Adapter adapter(adapter_config_from_json(running).value(), nullptr);
    return adapter.reload(adapter_config_from_json(next).value());
}

ConfigReload agent_reload(const Json& running, const Json& next) {
    // instances and instance are read only in a usable combination (above 1
    // with share_group "", instance below instances): when `next` changes
    // one of them, both documents get the rest of such a combination, so the
    // changed key is still the only difference.
    Json r = running, n = next;
    const unsigned instances = n.value("instances", 1u), instance = n.value("instance", 0u);
    if (instances > 1 || instance > 0) {
        r["share_group"] = n["share_group"] = "";
        if (instance >= instances) r["instances"] = n["instances"] = instance + 1;
    }
    AgentConfig a = agent_config_from_json(r).value();
    AgentConfig b = agent_config_from_json(n).value();
    // The loopback broker has no shared subscriptions: run without, and let
    // only a changed share_group count as one.
    const bool share_group_changed = b.share_group != a.share_group;
    a.share_group.clear();
    b.share_group = share_group_changed ? "changed" : "";
    LoopbackBroker broker;
    Agent agent(a);
    LoopbackOptions options;
    options.client_id = "schema-test-agent";
    agent.use_transport(make_loopback_transport(broker, options));
    REQUIRE(agent.start().ok());
    auto report = agent.reload(b);
    agent.stop(std::chrono::milliseconds(0));
    REQUIRE(report.ok());
    return std::move(report).value();
}

// Bridge::reload compares and applies without the bridge started (no sockets).
ConfigReload bridge_reload(const Json& running, const Json& next) {
    bridge::Bridge b(bridge::bridge_config_from_json(running).value(), Logger{});
    return b.reload(bridge::bridge_config_from_json(next).value());
}

const std::map<std::string, Reload> kReloads = {{"adapter", &adapter_reload}, {"agent", &agent_reload}, {"bridge", &bridge_reload}};

}  // namespace

TEST_CASE("schemas: one per configuration kind, the program carries the repository's") {
    std::set<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(kSchemaDir)) {
        const std::string name = entry.path().filename().string();
        const std::string suffix = ".schema.json";
        if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
            files.insert(name.substr(0, name.size() - suffix.size()));
    }
    std::set<std::string> kinds;
    for (const auto& kind : config_kinds()) kinds.insert(kind.name);
    CHECK(files == kinds);
    for (const auto& kind : config_kinds()) {
        INFO(kind.name);
        const auto built_in = config_schema(kind.name);
        REQUIRE(built_in.has_value());
        CHECK(*built_in == read_json(kSchemaDir / (std::string(kind.name) + ".schema.json")));
        CHECK((*built_in)["$schema"] == "https://json-schema.org/draft/2020-12/schema");
    }
}

TEST_CASE("schemas: every key the schema lists is read, every key the reader reads is listed") {
    for (const auto& kind : config_kinds()) {
        const Json schema = *config_schema(kind.name);
        const Json example = document(schema, changed_value);
        const Json defaults = document(schema, default_value);
        {
            INFO(kind.name << ": every key of the schema, set to a changed value: " << example.dump());
            auto r = kind.check(example);
            INFO((r.ok() ? "" : r.error().message));
            CHECK(r.ok());
        }
        {
            INFO(kind.name << ": every key of the schema at its stated default: " << defaults.dump());
            auto r = kind.check(defaults);
            INFO((r.ok() ? "" : r.error().message));
            CHECK(r.ok());
        }
        for_each_object(schema, "", [&](const Json& node, const std::string& pointer) {
            INFO(kind.name << " " << (pointer.empty() ? "/" : pointer));
            Json doc = example;
            Json value = is_map(node) ? document(node["additionalProperties"], changed_value) : Json(1);
            doc[Json::json_pointer(pointer)]["zz_not_a_key"] = value;
            auto r = kind.check(doc);
            if (is_map(node)) {  // any member name is the user's
                INFO((r.ok() ? "" : r.error().message));
                CHECK(r.ok());
                return;
            }
            REQUIRE_FALSE(r.ok());
            CHECK(r.error().code == ErrorCode::keys_of_arguments);
            CHECK(r.error().pointer == pointer + "/zz_not_a_key");
            std::set<std::string> listed;
            for (const auto& [key, _] : node["properties"].items()) listed.insert(key);
            CHECK(valid_keys_in(r.error().message) == listed);
        });
    }
}

TEST_CASE("schemas: the reload class of every key is what the program does on SIGHUP") {
    for (const auto& kind : config_kinds()) {
        const auto reload = kReloads.find(kind.name);
        if (reload == kReloads.end()) {
            WARN(kind.name << ": no reload check for this kind");
            continue;
        }
        const Json schema = *config_schema(kind.name);
        const Json defaults = document(schema, default_value);
        std::vector<Leaf> leaves;
        for_each_leaf(schema, "", "", "", leaves);
        for (const auto& leaf : leaves) {
            INFO(kind.name << " " << leaf.path << " (" << leaf.reload << ")");
            REQUIRE((leaf.reload == "reload" || leaf.reload == "restart"));
            Json next = defaults;
            next[Json::json_pointer(leaf.pointer)] = changed_value(leaf.schema);
            const ConfigReload report = reload->second(defaults, next);
            auto covers = [&](const std::vector<std::string>& keys) {
                return std::any_of(keys.begin(), keys.end(),
                                   [&](const std::string& k) { return k == leaf.path || leaf.path.rfind(k + ".", 0) == 0; });
            };
            INFO("applied " << Json(report.applied).dump() << ", restart " << Json(report.restart_needed).dump());
            CHECK(report.applied.size() + report.restart_needed.size() == 1);
            CHECK(covers(leaf.reload == "reload" ? report.applied : report.restart_needed));
        }
    }
}
