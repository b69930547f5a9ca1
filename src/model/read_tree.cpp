// Reads the object tree of a probe file (chapter 6). Every deviation becomes a
// Problem; the reader never stops early, so one pass lists them all. Aliases
// seen in deployed files (dataType, settable, "true") are understood here and
// normalized, so the rest of nclink sees only chapter-6 spelling.
//
// Longer than 500 lines on purpose: the readers of device, component, data
// item, sample channel, method and config call each other down the tree and
// share one problem sink and one id table; each is short, and split across
// files they would need that shared state in a header of its own that no
// other module may use.
#include "model/read_tree.hpp"

#include "model/vocabulary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <string_view>

namespace nclink::model_detail {
namespace {

constexpr std::string_view kRootType = "NC_LINK_ROOT";
constexpr std::string_view kChannelType = "SAMPLE_CHANNEL";
constexpr std::string_view kMethodType = "METHOD";
constexpr std::string_view kDefaultVersion = "1.0.0";

// Which array an object was found in decides what it may be (6.2.2-6.2.4):
// the root's configs hold data objects and methods, a device's configs data
// objects and sample channels (table 2), a component's configs data objects
// only (table 3; appendix A `ConfigsGen`).
enum class ListKind { root_configs, configs, component_configs, data_items };

// Table 36/42: a sample channel id is at most 16 bytes (it is the last
// segment of the Sample topic and the `id` of every Sample DTU).
constexpr std::size_t kMaxChannelIdBytes = 16;

struct Context {
    ListKind list = ListKind::configs;
    std::string device_id;    // "" for the root's configs
    std::string parent_id;    // root, device or component holding the list
    std::string parent_path;  // component path of that holder
    std::string list_key;     // "configs" or "dataItems"
};

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string path_segment(const std::string& type, const std::string& number) {
    std::string segment = type.empty() ? "?" : type;
    if (!number.empty()) segment += "@" + number;
    return segment;
}

// "1", "1.2", "1.2.3" -> parts; std::nullopt if anything else (leading
// zeros are parts too; the caller reports them).
std::optional<std::vector<std::string>> version_parts(const std::string& text) {
    std::vector<std::string> parts;
    std::string current;
    for (char c : text) {
        if (c == '.') {
            if (current.empty()) return std::nullopt;
            parts.push_back(current);
            current.clear();
        } else if (std::isdigit(static_cast<unsigned char>(c))) {
            current += c;
        } else {
            return std::nullopt;
        }
    }
    if (current.empty()) return std::nullopt;
    parts.push_back(current);
    if (parts.size() > 3) return std::nullopt;
    return parts;
}

// 6.2.5 note b: `source` names the types of every object on the path from
// the root to the component the data comes from, separated by ':'; objects
// of one type are told apart as "TYPE#number" ("NC_LINK_ROOT:MACHINE#0001:
// AXIS"). The note's own example writes " NCLINK_ROOT" (a space, no
// underscore): that spelling of the root is accepted too (docs/wire.md).
std::optional<std::string> source_syntax_error(std::string_view source) {
    auto trim = [](std::string_view t) {
        while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front()))) t.remove_prefix(1);
        while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.remove_suffix(1);
        return t;
    };
    const std::string_view text = trim(source);
    std::vector<std::string_view> segments;
    std::size_t start = 0;
    while (true) {
        const std::size_t colon = text.find(':', start);
        segments.push_back(text.substr(start, colon == std::string_view::npos ? std::string_view::npos : colon - start));
        if (colon == std::string_view::npos) break;
        start = colon + 1;
    }
    for (std::size_t i = 0; i < segments.size(); ++i) {
        const std::string_view seg = segments[i];
        if (seg.empty()) return fmt::format("segment {} is empty", i + 1);
        const std::size_t hash = seg.find('#');
        const std::string_view type = seg.substr(0, hash);
        if (type.empty()) return fmt::format("segment \"{}\" has no type", seg);
        for (char c : type)
            if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
                return fmt::format("type \"{}\" holds '{}' (types are letters, digits and '_')", type, c);
        if (hash != std::string_view::npos) {
            const std::string_view number = seg.substr(hash + 1);
            if (number.empty()) return fmt::format("segment \"{}\" has '#' but no number", seg);
            for (char c : number)
                if (c == '#' || std::isspace(static_cast<unsigned char>(c)))
                    return fmt::format("number \"{}\" of segment \"{}\" holds '{}'", number, seg, c);
        }
    }
    if (segments.front() != kRootType && segments.front() != "NCLINK_ROOT")
        return fmt::format("the path starts at \"{}\", not at the root ({})", segments.front(), kRootType);
    if (segments.size() < 2) return std::string("the path names no device below the root");
    return std::nullopt;
}

class Reader {
public:
    Reader(Problems& problems, ModelBuilder& builder) : problems_(problems), builder_(builder) {}

    void read_root(const Json& doc);
    std::vector<ChannelReference> take_references() { return std::move(references_); }

private:
    void read_device(const Json& obj, const std::string& ptr, const std::string& root_id);
    void read_component(const Json& obj, const std::string& ptr, const std::string& device_id, const std::string& parent_id,
                        const std::string& parent_path);
    void read_list(const Json& holder, const std::string& holder_ptr, const Context& ctx);
    void read_components(const Json& holder, const std::string& holder_ptr, const std::string& device_id,
                         const std::string& parent_id, const std::string& parent_path);
    void read_data_object(const Json& obj, const std::string& ptr, const Context& ctx);
    void read_channel(const Json& obj, const std::string& ptr, const Context& ctx);
    void read_method(const Json& obj, const std::string& ptr, const Context& ctx);

    std::optional<std::string> read_id(const Json& obj, const std::string& ptr);
    std::string read_string(const Json& obj, const std::string& ptr, const char* key);
    std::string read_type(const Json& obj, const std::string& ptr);
    std::string read_version(const Json& obj, const std::string& ptr, bool protocol);
    std::optional<double> read_interval(const Json& obj, const std::string& ptr, const char* key);
    Json unknown_attributes(const Json& obj, const std::string& ptr, std::initializer_list<std::string_view> known,
                            std::initializer_list<std::string_view> tolerated = {});
    const Json* array_attribute(const Json& holder, const std::string& holder_ptr, const char* key);
    void append_child(const std::string& parent_id, ListKind list, const std::string& id);
    void append_component(const std::string& parent_id, const std::string& id);

    Problems& problems_;
    ModelBuilder& builder_;
    std::vector<ChannelReference> references_;
    std::string root_type_{kRootType};
};

// ---- attribute readers ---------------------------------------------------

std::optional<std::string> Reader::read_id(const Json& obj, const std::string& ptr) {
    const std::string at = pointer_append(ptr, "id");
    const auto it = obj.find("id");
    if (it == obj.end()) {
        problems_.fatal(at, "missing required attribute \"id\": the object cannot be indexed");
        return std::nullopt;
    }
    if (it->is_number()) {
        problems_.conformance(at, fmt::format("\"id\" should be a string, not the number {}", it->dump()));
        return it->dump();
    }
    if (!it->is_string()) {
        problems_.fatal(at, fmt::format("\"id\" must be a string, not {}: the object cannot "
                                        "be indexed",
                                        it->type_name()));
        return std::nullopt;
    }
    std::string id = it->get<std::string>();
    if (id.empty()) {
        problems_.fatal(at, "empty \"id\": the object cannot be indexed");
        return std::nullopt;
    }
    return id;
}

std::string Reader::read_string(const Json& obj, const std::string& ptr, const char* key) {
    const auto it = obj.find(key);
    if (it == obj.end()) return {};
    if (it->is_string()) return it->get<std::string>();
    const std::string at = pointer_append(ptr, key);
    if (it->is_number() || it->is_boolean()) {
        problems_.conformance(at, fmt::format("\"{}\" should be a string, not {} (taken as "
                                              "\"{}\")",
                                              key, it->type_name(), it->dump()));
        return it->dump();
    }
    problems_.conformance(at, fmt::format("\"{}\" should be a string, not {}; ignored", key, it->type_name()));
    return {};
}

std::string Reader::read_type(const Json& obj, const std::string& ptr) {
    if (!obj.contains("type")) {
        problems_.conformance(pointer_append(ptr, "type"), "missing required attribute \"type\"");
        return {};
    }
    return read_string(obj, ptr, "type");
}

// Root `version` is the protocol version (1.x.x, table 1); a device `version`
// is the model file's version (1.x.x, table 2). Both default to 1.0.0 when absent.
std::string Reader::read_version(const Json& obj, const std::string& ptr, bool protocol) {
    const std::string at = pointer_append(ptr, "version");
    if (!obj.contains("version")) {
        problems_.conformance(at, fmt::format("missing required attribute \"version\" (taken "
                                              "as {})",
                                              kDefaultVersion));
        return std::string(kDefaultVersion);
    }
    std::string text = read_string(obj, ptr, "version");
    if (text.empty()) {
        if (obj["version"].is_string())
            problems_.conformance(at, fmt::format("empty \"version\" (taken as {})", kDefaultVersion));
        return std::string(kDefaultVersion);
    }
    // Table 1 (protocol) and table 2 (model file) both write the form
    // 1.x.x: three decimal numbers, the first 1. Appendix A's patterns allow
    // one digit per part; the tables' x does not say so, and nclink accepts
    // more (docs/wire.md).
    auto parts = version_parts(text);
    const std::string_view table = protocol ? "table 1" : "table 2";
    if (!parts) {
        problems_.conformance(at, fmt::format("version \"{}\" is not of the form 1.x.x ({})", text, table));
        return text;
    }
    const bool leading_zero =
        std::any_of(parts->begin(), parts->end(), [](const std::string& p) { return p.size() > 1 && p[0] == '0'; });
    const bool bad_major = (*parts)[0] != "1";
    if (parts->size() != 3 || bad_major || leading_zero) {
        // Reported, but kept as written: the version is the vendor's text,
        // announced in Probe/Version and returned in Probe/Query exactly as
        // given (8.2.5, 8.2.8), so "1.0" stays "1.0" on the wire.
        const std::string why = leading_zero ? ": a part with a leading zero" : bad_major ? ": the first number is not 1" : "";
        problems_.conformance(at, fmt::format("version \"{}\" is not of the form 1.x.x ({}){}", text, table, why));
    }
    return text;
}

std::optional<double> Reader::read_interval(const Json& obj, const std::string& ptr, const char* key) {
    const std::string at = pointer_append(ptr, key);
    const auto it = obj.find(key);
    if (it == obj.end()) {
        problems_.fatal(at, fmt::format("missing required attribute \"{}\"", key));
        return std::nullopt;
    }
    if (!it->is_number()) {
        problems_.fatal(at, fmt::format("\"{}\" must be a positive number of milliseconds, not "
                                        "{}",
                                        key, it->type_name()));
        return std::nullopt;
    }
    const double value = it->get<double>();
    if (!std::isfinite(value) || value <= 0) {
        problems_.fatal(at, fmt::format("\"{}\" must be a positive number of milliseconds, not "
                                        "{}",
                                        key, it->dump()));
        return std::nullopt;
    }
    if (!it->is_number_integer() && !it->is_number_unsigned() && std::floor(value) != value)
        problems_.conformance(at, fmt::format("\"{}\" {} is not an integer (appendix A: "
                                              "positive integer milliseconds)",
                                              key, it->dump()));
    return value;
}

Json Reader::unknown_attributes(const Json& obj, const std::string& ptr, std::initializer_list<std::string_view> known,
                                std::initializer_list<std::string_view> tolerated) {
    Json extra = Json::object();
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        const std::string& key = it.key();
        if (std::find(known.begin(), known.end(), key) != known.end()) continue;
        extra[key] = it.value();
        if (std::find(tolerated.begin(), tolerated.end(), key) != tolerated.end()) continue;
        problems_.warning(pointer_append(ptr, key), fmt::format("unknown attribute \"{}\" (kept)", key));
    }
    return extra;
}

const Json* Reader::array_attribute(const Json& holder, const std::string& holder_ptr, const char* key) {
    const auto it = holder.find(key);
    if (it == holder.end()) return nullptr;
    if (!it->is_array()) {
        problems_.conformance(pointer_append(holder_ptr, key),
                              fmt::format("\"{}\" should be an array, not {}; ignored", key, it->type_name()));
        return nullptr;
    }
    return &*it;
}

void Reader::append_child(const std::string& parent_id, ListKind list, const std::string& id) {
    if (Children* children = builder_.children_of(parent_id))
        (list == ListKind::data_items ? children->data_items : children->configs).push_back(id);
}

void Reader::append_component(const std::string& parent_id, const std::string& id) {
    if (Children* children = builder_.children_of(parent_id)) children->components.push_back(id);
}

// ---- objects -------------------------------------------------------------

void Reader::read_root(const Json& doc) {
    if (!doc.is_object()) {
        problems_.fatal("", fmt::format("the model must be a JSON object, not {}", doc.type_name()));
        return;
    }
    Root root;
    const auto id = read_id(doc, "");
    if (id) root.id = *id;
    root.name = read_string(doc, "", "name");
    if (doc.contains("type")) {
        root.type = read_string(doc, "", "type");
        if (root.type != kRootType && doc["type"].is_string())
            problems_.conformance("/type", fmt::format("root type must be {}, not \"{}\"", kRootType, root.type));
        if (root.type.empty()) root.type = kRootType;
    } else {
        problems_.conformance("/type", fmt::format("missing required attribute \"type\" (taken "
                                                   "as {})",
                                                   kRootType));
        root.type = kRootType;
    }
    root_type_ = root.type;
    root.description = read_string(doc, "", "description");
    root.version = read_version(doc, "", true);
    root.extra = unknown_attributes(doc, "", {"id", "name", "type", "description", "version", "configs", "devices"});

    const std::string root_id = id.value_or("");
    if (id) {
        ObjectInfo info{ObjectKind::root, *id, "", "", "/" + root.type, "", ""};
        builder_.set_root(std::move(root), std::move(info));
    }

    Context ctx{ListKind::root_configs, "", root_id, "/" + root_type_, "configs"};
    read_list(doc, "", ctx);

    const auto devices = doc.find("devices");
    if (devices == doc.end()) {
        problems_.fatal("/devices", "missing required attribute \"devices\": no usable device");
        return;
    }
    if (!devices->is_array()) {
        problems_.fatal("/devices", fmt::format("\"devices\" must be an array, not {}: no usable "
                                                "device",
                                                devices->type_name()));
        return;
    }
    for (std::size_t i = 0; i < devices->size(); ++i) {
        const std::string ptr = pointer_append("/devices", i);
        const Json& entry = (*devices)[i];
        if (!entry.is_object()) {
            problems_.conformance(ptr, fmt::format("device entry should be an object, not {}; "
                                                   "ignored",
                                                   entry.type_name()));
            continue;
        }
        read_device(entry, ptr, root_id);
    }
    if (builder_.model().devices().empty()) problems_.fatal("/devices", "no usable device");
}

void Reader::read_device(const Json& obj, const std::string& ptr, const std::string& root_id) {
    Device device;
    const auto id = read_id(obj, ptr);
    if (id) device.id = *id;
    device.name = read_string(obj, ptr, "name");
    device.type = read_type(obj, ptr);
    if (!device.type.empty() && !is_device_type(device.type)) {
        const auto hint = suggest_device_type(device.type);
        // A misspelt standard type (case, known abbreviation) deviates from
        // chapter 7: conformance. A type of its own is an extension the
        // standard allows: warning.
        const auto near = hint ? hint : nearest_device_type(device.type);
        problems_.add(
            hint ? Severity::conformance : Severity::warning, pointer_append(ptr, "type"),
            fmt::format("device type \"{}\" is not in table 7{}", device.type, near ? " (did you mean " + *near + "?)" : ""));
    }
    device.description = read_string(obj, ptr, "description");
    device.number = read_string(obj, ptr, "number");
    if (obj.contains("guid")) {
        std::string guid = read_string(obj, ptr, "guid");
        if (guid.empty())
            problems_.conformance(pointer_append(ptr, "guid"), "empty \"guid\": the terminal id falls back to the device id");
        else device.guid = std::move(guid);
    } else {
        problems_.conformance(pointer_append(ptr, "guid"),
                              "no \"guid\": the terminal id (dev_uuid) falls back to the "
                              "device id");
    }
    device.version = read_version(obj, ptr, false);
    device.extra = unknown_attributes(
        obj, ptr, {"id", "name", "type", "description", "number", "guid", "version", "configs", "dataItems", "components"});
    const std::string path = "/" + path_segment(device.type, device.number);
    // A device that cannot be indexed is fatal already; its children are
    // still read (under no parent) so every other problem gets reported too.
    std::string self;
    if (id) {
        ObjectInfo info{ObjectKind::device, *id, *id, root_id, path, ptr, ""};
        if (builder_.add_device(std::move(device), std::move(info))) {
            append_component(root_id, *id);
            self = *id;
        }
    }
    read_list(obj, ptr, Context{ListKind::configs, self, self, path, "configs"});
    read_list(obj, ptr, Context{ListKind::data_items, self, self, path, "dataItems"});
    read_components(obj, ptr, self, self, path);
}

void Reader::read_components(const Json& holder, const std::string& holder_ptr, const std::string& device_id,
                             const std::string& parent_id, const std::string& parent_path) {
    const Json* list = array_attribute(holder, holder_ptr, "components");
    if (list == nullptr) return;
    const std::string list_ptr = pointer_append(holder_ptr, "components");
    for (std::size_t i = 0; i < list->size(); ++i) {
        const std::string ptr = pointer_append(list_ptr, i);
        const Json& entry = (*list)[i];
        if (!entry.is_object()) {
            problems_.conformance(ptr, fmt::format("component entry should be an object, not "
                                                   "{}; ignored",
                                                   entry.type_name()));
            continue;
        }
        read_component(entry, ptr, device_id, parent_id, parent_path);
    }
}

void Reader::read_component(const Json& obj, const std::string& ptr, const std::string& device_id, const std::string& parent_id,
                            const std::string& parent_path) {
    Component component;
    const auto id = read_id(obj, ptr);
    if (id) component.id = *id;
    component.name = read_string(obj, ptr, "name");
    component.type = read_type(obj, ptr);
    if (!component.type.empty() && !is_component_type(component.type)) {
        const auto hint = suggest_component_type(component.type);
        // A misspelt standard type (case, known abbreviation) deviates from
        // chapter 7: conformance. A type of its own is an extension the
        // standard allows: warning.
        const auto near = hint ? hint : nearest_component_type(component.type);
        problems_.add(hint ? Severity::conformance : Severity::warning, pointer_append(ptr, "type"),
                      fmt::format("component type \"{}\" is not in table 8{}", component.type,
                                  near ? " (did you mean " + *near + "?)" : ""));
    }
    component.description = read_string(obj, ptr, "description");
    component.number = read_string(obj, ptr, "number");
    component.device_id = device_id;
    // appendix A lists `guid` for components although table 3 does not: kept, not reported.
    component.extra = unknown_attributes(
        obj, ptr, {"id", "name", "type", "description", "number", "configs", "dataItems", "components"}, {"guid"});
    const std::string path = parent_path + "/" + path_segment(component.type, component.number);
    std::string self;  // "" when not indexed: children are read, attached nowhere
    if (id) {
        ObjectInfo info{ObjectKind::component, *id, device_id, parent_id, path, ptr, ""};
        if (builder_.add_component(std::move(component), std::move(info))) {
            append_component(parent_id, *id);
            self = *id;
        }
    }
    read_list(obj, ptr, Context{ListKind::component_configs, device_id, self, path, "configs"});
    read_list(obj, ptr, Context{ListKind::data_items, device_id, self, path, "dataItems"});
    read_components(obj, ptr, device_id, self, path);
}

void Reader::read_list(const Json& holder, const std::string& holder_ptr, const Context& ctx) {
    const Json* list = array_attribute(holder, holder_ptr, ctx.list_key.c_str());
    if (list == nullptr) return;
    const std::string list_ptr = pointer_append(holder_ptr, ctx.list_key);
    for (std::size_t i = 0; i < list->size(); ++i) {
        const std::string ptr = pointer_append(list_ptr, i);
        const Json& entry = (*list)[i];
        if (!entry.is_object()) {
            problems_.conformance(ptr,
                                  fmt::format("{} entry should be an object, not {}; ignored", ctx.list_key, entry.type_name()));
            continue;
        }
        const auto type = entry.find("type");
        const bool typed = type != entry.end() && type->is_string();
        if (typed && *type == kChannelType) {
            if (ctx.list == ListKind::root_configs)
                problems_.conformance(ptr,
                                      "SAMPLE_CHANNEL object in the root configs: channels "
                                      "belong in device or component configs (6.2.3)");
            else if (ctx.list == ListKind::data_items)
                problems_.conformance(ptr,
                                      "SAMPLE_CHANNEL object in dataItems: channels belong "
                                      "in configs (6.2.3)");
            else if (ctx.list == ListKind::component_configs)
                problems_.conformance(ptr,
                                      "SAMPLE_CHANNEL object in a component's configs: "
                                      "channels belong in the device's configs (table 2; "
                                      "table 3 lists data objects only)");
            read_channel(entry, ptr, ctx);
        } else if (typed && *type == kMethodType) {
            if (ctx.list == ListKind::configs || ctx.list == ListKind::component_configs)
                problems_.conformance(ptr,
                                      "METHOD object outside the root configs: methods may "
                                      "only be defined in the root configs (6.2.7)");
            else if (ctx.list == ListKind::data_items)
                problems_.conformance(ptr,
                                      "METHOD object in dataItems: methods may only be "
                                      "defined in the root configs (6.2.7)");
            read_method(entry, ptr, ctx);
        } else {
            read_data_object(entry, ptr, ctx);
        }
    }
}

void Reader::read_data_object(const Json& obj, const std::string& ptr, const Context& ctx) {
    DataObject data;
    const auto id = read_id(obj, ptr);
    if (id) data.id = *id;
    data.name = read_string(obj, ptr, "name");
    data.type = read_type(obj, ptr);
    if (!data.type.empty() && !is_data_type(data.type)) {
        const auto hint = suggest_data_type(data.type);
        // A misspelt standard type (case, known abbreviation) deviates from
        // chapter 7: conformance. A type of its own is an extension the
        // standard allows: warning.
        const auto near = hint ? hint : nearest_data_type(data.type);
        problems_.add(hint ? Severity::conformance : Severity::warning, pointer_append(ptr, "type"),
                      fmt::format("data type \"{}\" is not in tables 10, 12, 13{}", data.type,
                                  near ? " (did you mean " + *near + "?)" : ""));
    }
    data.description = read_string(obj, ptr, "description");
    data.source = read_string(obj, ptr, "source");
    if (!data.source.empty()) {
        if (auto why = source_syntax_error(data.source))
            problems_.conformance(pointer_append(ptr, "source"),
                                  fmt::format("source \"{}\" is not a path of types from the root "
                                              "(TYPE or TYPE#number, separated by ':', 6.2.5 note b): {}",
                                              data.source, *why));
    }
    data.units = read_string(obj, ptr, "units");
    if (!data.units.empty() && !is_known_unit(data.units)) {
        const auto near = nearest_unit(data.units);
        problems_.warning(pointer_append(ptr, "units"),
                          fmt::format("units \"{}\" are not in tables 10/11 or appendix A{} (docs/vocabulary.md)", data.units,
                                      near ? " (did you mean " + *near + "?)" : ""));
    }

    // datatype: chapter 6 spells it `datatype` with "list"/"dict"; HNC files
    // and appendix B write `dataType` with "LIST"/"DICT".
    const char* datatype_key = obj.contains("datatype") ? "datatype" : obj.contains("dataType") ? "dataType" : nullptr;
    if (obj.contains("datatype") && obj.contains("dataType"))
        problems_.conformance(pointer_append(ptr, "dataType"), "both \"datatype\" and \"dataType\" given; \"dataType\" ignored");
    if (datatype_key != nullptr) {
        const Json& v = obj[datatype_key];
        const std::string at = pointer_append(ptr, datatype_key);
        const bool alias = std::string_view(datatype_key) != "datatype";
        if (!v.is_string()) {
            problems_.conformance(at, fmt::format("\"{}\" should be the string \"list\" or "
                                                  "\"dict\", not {}; taken as single",
                                                  datatype_key, v.type_name()));
        } else {
            const std::string text = v.get<std::string>();
            const std::string low = lower(text);
            if (low == "list" || low == "dict" || low == "file") {
                // "file": 6.2.1 names it a data type beside list and dict;
                // table 4 lists only those two. Both readings are accepted.
                data.kind = low == "list" ? DataKind::list : low == "dict" ? DataKind::dict : DataKind::single;
                data.datatype_file = low == "file";
                if (alias || text != low)
                    problems_.conformance(at, fmt::format("\"{}\": \"{}\" should be \"datatype\": "
                                                          "\"{}\"",
                                                          datatype_key, text, low));
            } else {
                problems_.conformance(at, fmt::format("unknown {} \"{}\" (list, dict or file; absent "
                                                      "means single); taken as single",
                                                      datatype_key, text));
            }
        }
    }

    if (const auto it = obj.find("value"); it != obj.end()) {
        data.value = *it;
        if (data.kind == DataKind::list && !it->is_array())
            problems_.conformance(pointer_append(ptr, "value"), fmt::format("value is {} but datatype is list", it->type_name()));
        if (data.kind == DataKind::dict && !it->is_object())
            problems_.conformance(pointer_append(ptr, "value"), fmt::format("value is {} but datatype is dict", it->type_name()));
    }

    // setable: a boolean per table 4; deployed files write `settable` and
    // the standard's own example 6.2.5 writes the string "true".
    const char* setable_key = obj.contains("setable") ? "setable" : obj.contains("settable") ? "settable" : nullptr;
    if (obj.contains("setable") && obj.contains("settable"))
        problems_.conformance(pointer_append(ptr, "settable"), "both \"setable\" and \"settable\" given; \"settable\" ignored");
    if (setable_key != nullptr) {
        const Json& v = obj[setable_key];
        const std::string at = pointer_append(ptr, setable_key);
        const bool alias = std::string_view(setable_key) != "setable";
        const std::string spelled = alias ? "\"settable\" should be spelled \"setable\"" : "";
        if (v.is_boolean()) {
            data.setable = v.get<bool>();
            if (alias) problems_.conformance(at, spelled);
        } else if (v.is_string() && (lower(v.get<std::string>()) == "true" || lower(v.get<std::string>()) == "false")) {
            data.setable = lower(v.get<std::string>()) == "true";
            problems_.conformance(at, fmt::format("{}{}setable should be the boolean {}, not the "
                                                  "string {}",
                                                  spelled, alias ? "; " : "", data.setable ? "true" : "false", v.dump()));
        } else {
            problems_.conformance(at, fmt::format("{}{}setable should be a boolean, not {}; "
                                                  "taken as false",
                                                  spelled, alias ? "; " : "", v.type_name()));
        }
    }

    data.config = ctx.list != ListKind::data_items;
    data.device_id = ctx.device_id;
    data.extra = unknown_attributes(
        obj, ptr,
        {"id", "name", "type", "description", "datatype", "dataType", "value", "source", "units", "setable", "settable"});
    if (!id) return;
    const std::string path = ctx.parent_path + "/" + path_segment(data.type, "");
    const ObjectKind kind = data.config ? ObjectKind::config_item : ObjectKind::data_item;
    ObjectInfo info{kind, *id, ctx.device_id, ctx.parent_id, path, ptr, data.source};
    if (builder_.add_data_object(std::move(data), std::move(info))) append_child(ctx.parent_id, ctx.list, *id);
}

void Reader::read_channel(const Json& obj, const std::string& ptr, const Context& ctx) {
    SampleChannel channel;
    const auto id = read_id(obj, ptr);
    if (id) channel.id = *id;
    if (id && id->size() > kMaxChannelIdBytes)
        problems_.conformance(pointer_append(ptr, "id"),
                              fmt::format("sample channel id \"{}\" is {} bytes; tables 36 and 42 allow at "
                                          "most {}",
                                          *id, id->size(), kMaxChannelIdBytes));
    channel.name = read_string(obj, ptr, "name");
    channel.description = read_string(obj, ptr, "description");
    channel.device_id = ctx.device_id;
    std::vector<ChannelReference> refs;

    const std::string ids_ptr = pointer_append(ptr, "ids");
    const auto ids = obj.find("ids");
    if (ids == obj.end()) {
        problems_.conformance(ids_ptr, "missing required attribute \"ids\"");
    } else if (!ids->is_array()) {
        problems_.conformance(ids_ptr, fmt::format("\"ids\" should be an array, not {}; ignored", ids->type_name()));
    } else {
        for (std::size_t i = 0; i < ids->size(); ++i) {
            const Json& entry = (*ids)[i];
            const std::string at = pointer_append(ids_ptr, i);
            std::string item;
            if (entry.is_object() && entry.contains("id") && entry["id"].is_string()) {
                item = entry["id"].get<std::string>();
            } else if (entry.is_string()) {
                problems_.conformance(at,
                                      "ids entry should be an object {\"id\": ...}, not a "
                                      "string");
                item = entry.get<std::string>();
            }
            if (item.empty()) {
                problems_.conformance(at, "ids entry names no data item id; ignored");
                continue;
            }
            channel.ids.push_back(item);
            refs.push_back(ChannelReference{id.value_or(""), item, at});
        }
    }

    const auto sample = read_interval(obj, ptr, "sampleInterval");
    const auto upload = read_interval(obj, ptr, "uploadInterval");
    if (sample) channel.sample_interval_ms = *sample;
    if (upload) channel.upload_interval_ms = *upload;
    // An upload period shorter than the sample period cannot carry one row
    // (6.2.6.2: a DTU holds rows sampleInterval apart): the channel could
    // never run, so the model cannot be run as written.
    if (sample && upload && *upload < *sample)
        problems_.fatal(pointer_append(ptr, "uploadInterval"),
                        fmt::format("uploadInterval {} is shorter than sampleInterval {}: the channel "
                                    "cannot upload what it samples",
                                    *upload, *sample));
    channel.extra = unknown_attributes(obj, ptr, {"id", "name", "type", "description", "ids", "sampleInterval", "uploadInterval"});
    if (!id) return;
    const std::string path = ctx.parent_path + "/" + std::string(kChannelType);
    ObjectInfo info{ObjectKind::sample_channel, *id, ctx.device_id, ctx.parent_id, path, ptr, ""};
    if (builder_.add_channel(std::move(channel), std::move(info))) {
        append_child(ctx.parent_id, ctx.list, *id);
        references_.insert(references_.end(), refs.begin(), refs.end());
    }
}

void Reader::read_method(const Json& obj, const std::string& ptr, const Context& ctx) {
    Method method;
    const auto id = read_id(obj, ptr);
    if (id) method.id = *id;
    method.name = read_string(obj, ptr, "name");
    method.description = read_string(obj, ptr, "description");
    const auto args = obj.find("args");
    if (args == obj.end() || args->is_null()) {
        problems_.conformance(pointer_append(ptr, "args"), "missing required attribute \"args\"");
    } else if (!args->is_object() && !args->is_array()) {
        // Table 6 says array, its example and appendix A an object: accept both.
        problems_.conformance(pointer_append(ptr, "args"),
                              fmt::format("\"args\" should be an object or array, not {}", args->type_name()));
        method.args = *args;
    } else {
        method.args = *args;
    }
    method.extra = unknown_attributes(obj, ptr, {"id", "name", "type", "description", "args"});
    if (!id) return;
    const std::string path = ctx.parent_path + "/" + std::string(kMethodType);
    ObjectInfo info{ObjectKind::method, *id, ctx.device_id, ctx.parent_id, path, ptr, ""};
    if (builder_.add_method(std::move(method), std::move(info))) append_child(ctx.parent_id, ctx.list, *id);
}

}  // namespace

ReadOutcome read_document(const Json& document, Problems& problems, ModelBuilder& builder) {
    Reader reader(problems, builder);
    reader.read_root(document);
    return ReadOutcome{reader.take_references()};
}

}  // namespace nclink::model_detail
