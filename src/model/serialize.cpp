// Model -> probe document. Writes chapter-6 spelling in the attribute order of
// tables 1-6 (not alphabetical), so a vendor can read and diff the output.
#include <nclink/model.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace nclink {
namespace {

using Ordered = nlohmann::ordered_json;

void put_string(Ordered& out, const char* key, const std::string& value) {
    if (!value.empty()) out[key] = value;
}

// Unknown attributes follow the known ones, unchanged.
void put_extra(Ordered& out, const Json& extra) {
    if (!extra.is_object()) return;
    for (auto it = extra.begin(); it != extra.end(); ++it) out[it.key()] = Ordered(it.value());
}

// Integral intervals are written as integers ("sampleInterval": 1, not 1.0).
Ordered number(double value) {
    if (std::floor(value) == value && std::fabs(value) < 9.0e15) return Ordered(static_cast<std::int64_t>(value));
    return Ordered(value);
}

class Writer {
public:
    explicit Writer(const Model& model) : model_(model) {}

    Ordered root() const {
        const Root& r = model_.root();
        Ordered out = Ordered::object();
        put_string(out, "id", r.id);
        put_string(out, "name", r.name);
        put_string(out, "type", r.type);
        put_string(out, "description", r.description);
        put_string(out, "version", r.version);
        put_list(out, "configs", r.children.configs);
        Ordered devices = Ordered::array();
        for (const auto& id : r.children.components)
            if (const Device* d = model_.device(id)) devices.push_back(device(*d));
        out["devices"] = std::move(devices);
        put_extra(out, r.extra);
        return out;
    }

private:
    Ordered device(const Device& d) const {
        Ordered out = Ordered::object();
        put_string(out, "id", d.id);
        put_string(out, "name", d.name);
        put_string(out, "type", d.type);
        put_string(out, "description", d.description);
        put_string(out, "number", d.number);
        if (d.guid) out["guid"] = *d.guid;
        put_string(out, "version", d.version);
        put_children(out, d.children);
        put_extra(out, d.extra);
        return out;
    }

    Ordered component(const Component& c) const {
        Ordered out = Ordered::object();
        put_string(out, "id", c.id);
        put_string(out, "name", c.name);
        put_string(out, "type", c.type);
        put_string(out, "description", c.description);
        put_string(out, "number", c.number);
        put_children(out, c.children);
        put_extra(out, c.extra);
        return out;
    }

    Ordered data_object(const DataObject& d) const {
        Ordered out = Ordered::object();
        put_string(out, "id", d.id);
        put_string(out, "name", d.name);
        put_string(out, "type", d.type);
        put_string(out, "description", d.description);
        if (d.kind != DataKind::single) out["datatype"] = std::string(to_string(d.kind));
        else if (d.datatype_file) out["datatype"] = "file";
        if (d.value) out["value"] = Ordered(*d.value);
        put_string(out, "source", d.source);
        put_string(out, "units", d.units);
        if (d.setable) out["setable"] = true;
        put_extra(out, d.extra);
        return out;
    }

    Ordered channel(const SampleChannel& c) const {
        Ordered out = Ordered::object();
        put_string(out, "id", c.id);
        put_string(out, "name", c.name);
        out["type"] = "SAMPLE_CHANNEL";
        put_string(out, "description", c.description);
        out["sampleInterval"] = number(c.sample_interval_ms);
        out["uploadInterval"] = number(c.upload_interval_ms);
        Ordered ids = Ordered::array();
        for (const auto& id : c.ids) ids.push_back(Ordered{{"id", id}});
        out["ids"] = std::move(ids);
        put_extra(out, c.extra);
        return out;
    }

    Ordered method(const Method& m) const {
        Ordered out = Ordered::object();
        put_string(out, "id", m.id);
        put_string(out, "name", m.name);
        out["type"] = "METHOD";
        put_string(out, "description", m.description);
        if (!m.args.is_null()) out["args"] = Ordered(m.args);
        put_extra(out, m.extra);
        return out;
    }

    Ordered object(const std::string& id) const {
        if (const DataObject* d = model_.data_object(id)) return data_object(*d);
        if (const SampleChannel* c = model_.channel(id)) return channel(*c);
        if (const Method* m = model_.method(id)) return method(*m);
        return Ordered();  // unreachable: lists only hold indexed ids
    }

    void put_list(Ordered& out, const char* key, const std::vector<std::string>& ids) const {
        if (ids.empty()) return;
        Ordered list = Ordered::array();
        for (const auto& id : ids) list.push_back(object(id));
        out[key] = std::move(list);
    }

    void put_children(Ordered& out, const Children& children) const {
        put_list(out, "configs", children.configs);
        put_list(out, "dataItems", children.data_items);
        if (children.components.empty()) return;
        Ordered list = Ordered::array();
        for (const auto& id : children.components)
            if (const Component* c = model_.component(id)) list.push_back(component(*c));
        out["components"] = std::move(list);
    }

    const Model& model_;
};

}  // namespace

Json model_to_json(const Model& model) { return Json(Writer(model).root()); }

std::string serialize_model(const Model& model) {
    // replace: strings are valid UTF-8 after load, but dump must never throw.
    return Writer(model).root().dump(2, ' ', false, Ordered::error_handler_t::replace) + "\n";
}

}  // namespace nclink
