// `nclink probe --device GUID [--json]`: fetch the device's model (Probe/Query)
// and print it as a tree of devices, components, data items, sample channels
// and methods; --json prints the model itself.
#include "cli_device.hpp"

#include <nclink/model.hpp>

#include <cstdio>
#include <string>

namespace nclink::cli {

const char* const probe_usage =
    "usage: nclink probe --device GUID [options]\n"
    "  Fetches the device's model (Probe/Query) and prints a summary: devices,\n"
    "  the component tree with types, data items (id, type, datatype, setable),\n"
    "  sample channels with their intervals, and methods. --json prints the model.\n" NCLINK_CLI_GLOBAL_OPTIONS;

namespace {

std::string format_interval(double ms) {
    char text[32];
    std::snprintf(text, sizeof text, "%g ms", ms);
    return text;
}

void print_line(int depth, const std::string& text) { std::printf("%*s%s\n", depth * 2, "", text.c_str()); }

std::string quoted_name(const std::string& name) { return name.empty() ? "" : "  \"" + name + "\""; }

// Kinds come from where an object sits in the model (the model engine knows),
// not from which attributes it happens to carry.
void print_ids(const Model& model, const std::vector<std::string>& ids, int depth);

void print_component(const Model& model, const Component& c, int depth) {
    print_line(depth, "component " + c.id + "  " + c.type + (c.number.empty() ? "" : "@" + c.number) + quoted_name(c.name));
    print_ids(model, c.children.configs, depth + 1);
    print_ids(model, c.children.data_items, depth + 1);
    print_ids(model, c.children.components, depth + 1);
}

void print_ids(const Model& model, const std::vector<std::string>& ids, int depth) {
    for (const auto& id : ids) {
        const ObjectInfo* info = model.find(id);
        if (!info) continue;
        switch (info->kind) {
            case ObjectKind::data_item:
            case ObjectKind::config_item: {
                const DataObject& d = *model.data_object(id);
                std::string line = std::string(info->kind == ObjectKind::config_item ? "config " : "item ") + id + "  " + d.type;
                if (d.kind != DataKind::single) line += "  " + std::string(to_string(d.kind));
                if (d.setable) line += "  setable";
                if (!d.units.empty()) line += "  units=" + d.units;
                line += quoted_name(d.name);
                if (d.value) line += "  = " + d.value->dump(-1, ' ', false, Json::error_handler_t::replace);
                print_line(depth, line);
                break;
            }
            case ObjectKind::sample_channel: {
                const SampleChannel& ch = *model.channel(id);
                std::string points;
                for (const auto& p : ch.ids) points += (points.empty() ? "" : ", ") + p;
                print_line(depth, "channel " + id + "  sample every " + format_interval(ch.sample_interval_ms) +
                                      ", upload every " + format_interval(ch.upload_interval_ms) + "  [" + points + "]");
                break;
            }
            case ObjectKind::method: {
                const Method& m = *model.method(id);
                std::string line = "method " + id + quoted_name(m.name);
                if (m.args.is_object() && !m.args.empty()) {
                    std::string keys;
                    for (const auto& [k, v] : m.args.items()) keys += (keys.empty() ? "" : ", ") + k;
                    line += "  args: " + keys;
                }
                print_line(depth, line);
                break;
            }
            case ObjectKind::component: print_component(model, *model.component(id), depth); break;
            case ObjectKind::device: {
                const Device& d = *model.device(id);
                print_line(depth, "device " + id + "  " + d.type + quoted_name(d.name) + "  dev_uuid=" + resolve_dev_uuid(d) +
                                      "  version=" + d.version);
                print_ids(model, d.children.configs, depth + 1);
                print_ids(model, d.children.data_items, depth + 1);
                print_ids(model, d.children.components, depth + 1);
                break;
            }
            case ObjectKind::root: break;
        }
    }
}

int print_summary(const Json& probe) {
    const LoadResult loaded = parse_model(probe.dump(-1, ' ', false, Json::error_handler_t::replace));
    if (!loaded.model) {
        std::fprintf(stderr, "nclink probe: the device sent a model with fatal problems:\n");
        for (const auto& p : loaded.problems)
            std::fprintf(stderr, "  %s: %s: %s\n", p.pointer.empty() ? "/" : p.pointer.c_str(),
                         std::string(to_string(p.severity)).c_str(), p.message.c_str());
        return 1;
    }
    const Model& model = *loaded.model;
    const Root& root = model.root();
    print_line(0, "model " + root.id + quoted_name(root.name) + "  version=" + root.version);
    print_ids(model, root.children.configs, 1);
    print_ids(model, root.children.components, 1);  // the devices
    std::size_t conformance = loaded.count(Severity::conformance), warnings = loaded.count(Severity::warning);
    if (conformance + warnings > 0)
        print_line(0, std::to_string(conformance) + " conformance problem(s), " + std::to_string(warnings) +
                          " warning(s): save it with --json and run `nclink validate` for details");
    return 0;
}

}  // namespace

int run_probe(const Args& args) {
    CliOptions options;
    if (parse_device_command(args, {}, probe_usage, options)) return 0;
    if (!options.positionals.empty()) throw UsageError{"unexpected argument " + options.positionals.front()};
    auto client = connect_client(options);
    auto model = client->probe(options.device);
    if (!model) {
        std::fprintf(stderr, "nclink probe: %s\n", model.error().describe().c_str());
        return 1;
    }
    if (options.json) {
        std::printf("%s\n", model->dump(2, ' ', false, Json::error_handler_t::replace).c_str());
        return 0;
    }
    return print_summary(*model);
}

}  // namespace nclink::cli
