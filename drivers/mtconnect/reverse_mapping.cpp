#include "mtconnect/reverse_mapping.hpp"

#include "mapping/mapping_table.hpp"

#include <nclink/mapping.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <cmath>
#include <functional>
#include <set>

namespace nclink::mtconnect {

namespace md = nclink::mapping_detail;

namespace {

std::string number_text(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

/// Where a component sits, as the appendix A rows ask it (mapping_table.hpp).
enum class Place { device, controller, axis, in_axis, other };

md::Placement placement_of(Place place) {
    md::Placement p;
    p.on_device = place == Place::device;
    p.on_controller = place == Place::controller;
    p.on_axis = place == Place::axis;
    p.in_axis = place == Place::in_axis;
    return p;
}

std::string_view to_category(MtCategory c) {
    return c == MtCategory::sample ? "SAMPLE" : c == MtCategory::condition ? "CONDITION" : "EVENT";
}

/// The NC-Link type whose forward mapping at `place` is this DataItem's
/// category/type/subType. `exact` false: only the subType differs.
const md::DataTypeRow* reverse_row(const ProbeItem& item, Place place, bool rotary, bool& exact) {
    const md::Placement p = placement_of(place);
    std::set<std::string_view> tried;
    const md::DataTypeRow* first = nullptr;
    const md::DataTypeRow* loose = nullptr;
    for (std::size_t i = 0; i < md::data_row_count(); ++i) {
        const std::string_view type = md::data_row(i).type;
        if (!tried.insert(type).second) continue;
        const md::DataTypeRow* row = md::find_data_row(type, p);  // the row the forward direction uses here
        if (!row || row->mt_fallback || to_category(row->category) != item.category || row->mt_type != item.type) continue;
        if (row->mt_sub_type == item.sub_type) {
            if (rotary && type.substr(0, 8) == "SPINDLE_") {
                exact = true;
                return row;
            }
            if (!first) first = row;
        } else if (!loose) {
            loose = row;
        }
    }
    exact = first != nullptr;
    return first ? first : loose;
}

/// The NC-Link unit spelling for MTConnect units/nativeUnits; `preferred`
/// (the type's default) first. nullptr when no row matches.
const md::UnitRow* reverse_unit(const std::string& units, const std::string& native_units, std::string_view preferred) {
    auto fits = [&](const md::UnitRow& u) {
        if (md::mtconnect_units(u.dimension) != units) return false;
        if (native_units.empty() || native_units == units) return u.native_units.empty() && u.scale == 1 && u.offset == 0;
        return u.native_units == native_units;
    };
    if (!preferred.empty())
        if (const md::UnitRow* u = md::find_unit(preferred); u && fits(*u)) return u;
    // The table has no iterator: every spelling the units of a dimension may
    // take is found by asking for the names the table spells them with.
    for (std::string_view s : {std::string_view(native_units), std::string_view(units)}) {
        if (s.empty()) continue;
        if (const md::UnitRow* u = md::find_unit(s); u && fits(*u)) return u;
    }
    return nullptr;
}

struct Builder {
    const ProbeComponent& device;
    ReverseModel& out;
    std::string prefix;         ///< "<uuid>." when every id carries it (nclink-bridge)
    std::set<std::string> ids;  ///< NC-Link ids taken
    int min_interval = 100;
    std::map<int, std::vector<std::string>> by_interval;  ///< sampleInterval ms -> NC-Link ids (sample channels)

    std::string nclink_id(const std::string& mt_id) const {
        std::string rest = mt_id;
        if (!prefix.empty() && rest.compare(0, prefix.size(), prefix) == 0) rest = rest.substr(prefix.size());
        if (auto decoded = nclink_id_from_mtconnect(rest)) return *decoded;
        return rest;
    }

    std::string unique(std::string id) {
        std::string candidate = id;
        for (int n = 2; ids.count(candidate); ++n) candidate = id + "_" + std::to_string(n);
        ids.insert(candidate);
        return candidate;
    }

    Json fixed_config(const std::string& id, const char* type, const std::string& name, const std::string& text) {
        Json value = text;
        if (std::string_view(type) == "SERIAL_NUMBER" && !text.empty() &&
            text.find_first_not_of("0123456789") == std::string::npos && text.size() < 16)
            value = std::stoll(text);
        return Json{{"id", unique(id)}, {"name", name}, {"type", type}, {"value", value}};
    }

    void description_configs(const ProbeComponent& c, const std::string& owner_id, Json& configs) {
        static const std::pair<const char*, const char*> kAttrs[] = {
            {"manufacturer", "MANUFACTURER"}, {"model", "MODEL"}, {"serialNumber", "SERIAL_NUMBER"}};
        for (const auto& [attr, type] : kAttrs) {
            const auto it = c.description_attributes.find(attr);
            if (it == c.description_attributes.end() || it->second.empty()) continue;
            std::string id = owner_id + "_" + std::string(type);
            for (char& ch : id) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            for (char& ch : id) ch = ch == '.' ? '_' : ch;
            configs.push_back(fixed_config(id, type, attr, it->second));
        }
    }

    Result<void> item(const ProbeItem& item, Place place, bool rotary, Json& data_items, Json& configs) {
        ItemBinding b;
        b.mt_id = item.id;
        b.name = item.name;
        b.shdr_key = !item.source.empty() ? item.source : !item.name.empty() ? item.name : item.id;
        b.category = item.category;
        b.mt_type = item.type;
        if (item.type == "AVAILABILITY") {
            b.rule = ValueRule::availability;
            out.unmatched.push_back({item.id, "EVENT AVAILABILITY", "the machine link (no data item)"});
            return add(std::move(b));
        }
        const std::string mt_form = item.category + " " + item.type + (item.sub_type.empty() ? "" : "/" + item.sub_type);
        const md::DataTypeRow* row = nullptr;
        std::string description;
        if (item.category == "CONDITION") {
            b.nclink_type = "WARNING";
            b.rule = ValueRule::condition;
            if (item.type != "SYSTEM") {
                description = "MTConnect CONDITION " + item.type + " (read as WARNING)";
                out.notes.push_back(item.id + ": " + mt_form + " read as a WARNING item");
            }
        } else if (item.category == "EVENT" && item.type == "MESSAGE" && item.sub_type.rfind("x:", 0) == 0 &&
                   item.sub_type.size() > 2) {
            // nclink's own fallback (docs/mapping.md "Fallback"): the NC-Link type itself.
            b.nclink_type = item.sub_type.substr(2);
            row = md::find_data_row(b.nclink_type, placement_of(place));
        } else {
            bool exact = false;
            row = reverse_row(item, place, rotary, exact);
            if (row) {
                b.nclink_type = std::string(row->type);
                if (!exact)
                    out.notes.push_back(item.id + ": " + mt_form + " read as " + b.nclink_type + ", whose subType is " +
                                        std::string(row->mt_sub_type.empty() ? "none" : row->mt_sub_type));
            } else {
                b.nclink_type = item.type;
                description = "MTConnect " + mt_form + " (no NC-Link counterpart)";
                out.unmatched.push_back({item.id, mt_form, b.nclink_type + " (named in its description)"});
            }
        }
        // The value rule follows the row's value form and JSON type.
        if (b.rule != ValueRule::condition) {
            if (row && row->value_form == MtValueForm::enumerated) {
                b.rule = row->value_type == md::ValueType::boolean ? ValueRule::boolean : ValueRule::words;
                for (std::size_t i = 0; i < row->value_count; ++i) {
                    const std::string mt(row->values[i].mtconnect);
                    bool seen = false;
                    for (const auto& w : b.words) seen = seen || w.first == mt;
                    if (!seen) b.words.emplace_back(mt, std::string(row->values[i].nclink));  // the first word wins
                }
            } else if (item.category == "SAMPLE" || (row && row->value_form == MtValueForm::number)) {
                b.rule = item.units.size() > 3 && item.units.compare(item.units.size() - 3, 3, "_3D") == 0 ? ValueRule::number_3d
                                                                                                           : ValueRule::number;
            } else if (row) {
                switch (row->value_type) {
                    case md::ValueType::number: b.rule = ValueRule::number; break;
                    case md::ValueType::integer: b.rule = ValueRule::integer; break;
                    case md::ValueType::boolean: b.rule = ValueRule::boolean; break;
                    case md::ValueType::string: b.rule = ValueRule::text; break;
                    default: b.rule = ValueRule::json;
                }
            } else {
                b.rule = ValueRule::text;
            }
        }
        if (item.units.empty() && row && !row->default_units.empty() && b.rule != ValueRule::words &&
            b.rule != ValueRule::boolean && b.rule != ValueRule::condition) {
            // An EVENT carries no units in MTConnect (overrides are percent by
            // their type): the NC-Link type's own unit (tables 10, 13).
            b.units = std::string(row->default_units);
        } else if (!item.units.empty()) {
            const md::UnitRow* u = reverse_unit(item.units, item.native_units, row ? row->default_units : std::string_view());
            if (u) {
                b.units = std::string(u->spelling);
                b.scale = u->scale;
                b.offset = u->offset;
            } else {
                b.units = item.native_units.empty() ? item.units : item.native_units;
                if (!item.native_units.empty() && item.native_units != item.units)
                    out.notes.push_back(item.id + ": nativeUnits " + item.native_units + " unknown; values are in " + item.units +
                                        " as the agent sends them, units say " + b.units);
                if (!item.native_units.empty()) b.units = item.units;
            }
        }
        b.nclink_id = unique(nclink_id(item.id));
        Json j = {{"id", b.nclink_id}, {"name", item.name.empty() ? b.nclink_id : item.name}, {"type", b.nclink_type}};
        if (!b.units.empty()) j["units"] = b.units;
        if (!description.empty()) j["description"] = description;
        if (row && row->value_type == md::ValueType::list) j["datatype"] = "list";
        if (row && row->value_type == md::ValueType::dict) j["datatype"] = "dict";
        if (item.sample_rate > 0 && item.constraint_values.size() != 1) {
            const int exact = std::max(1, static_cast<int>(std::lround(1000.0 / item.sample_rate)));
            const int interval = std::max(min_interval, exact);
            by_interval[interval].push_back(b.nclink_id);
            if (interval != exact)
                out.notes.push_back(item.id + ": sampleRate " + number_text(item.sample_rate) + " sampled every " +
                                    std::to_string(interval) + " ms (values change no faster than the source is read)");
        }
        if (item.constraint_values.size() == 1) {
            b.fixed = true;
            j["value"] = fixed_value(b, item.constraint_values.front());
            configs.push_back(std::move(j));
        } else {
            data_items.push_back(std::move(j));
        }
        return add(std::move(b));
    }

    Json fixed_value(const ItemBinding& b, const std::string& text);

    Result<void> add(ItemBinding b) {
        const std::size_t index = out.items.size();
        if (!out.by_mt_id.emplace(b.mt_id, index).second)
            return make_error(ErrorCode::key_error, "probe: DataItem id " + b.mt_id + " appears twice");
        // An SHDR key names the DataItem by its Source, else its name, else its id.
        for (const std::string* key : {&b.shdr_key, &b.name, &b.mt_id})
            if (!key->empty()) out.by_shdr_key.emplace(*key, index);
        if (!b.nclink_id.empty()) out.by_nclink_id.emplace(b.nclink_id, index);
        out.items.push_back(std::move(b));
        return ok_result();
    }

    /// The items of `c` (and of the components folded into it) into `target`.
    Result<void> fill(const ProbeComponent& c, Place place, bool rotary, Json& target) {
        Json data_items = Json::array(), configs = Json::array(), components = Json::array();
        if (target.contains("dataItems")) data_items = target["dataItems"];
        if (target.contains("configs")) configs = target["configs"];
        if (target.contains("components")) components = target["components"];
        for (const auto& i : c.items)
            if (auto r = item(i, place, rotary, data_items, configs); !r) return r;
        for (const auto& sub : c.components) {
            // Organizers (Axes, Systems: MTConnect 1.4 part 2, 4.4) and a
            // Controller's Path hold nothing of their own in NC-Link terms.
            const bool fold =
                sub.element == "Axes" || sub.element == "Systems" || (sub.element == "Path" && place == Place::controller);
            if (fold) {
                // A container (Axes) or a Controller's Path: its content belongs to the parent.
                Json folded = {{"dataItems", data_items}, {"configs", configs}, {"components", components}};
                if (auto r = fill(sub, place, rotary, folded); !r) return r;
                data_items = folded["dataItems"];
                configs = folded["configs"];
                components = folded["components"];
                continue;
            }
            auto made = component(sub, place);
            if (!made.ok()) return std::move(made).error();
            components.push_back(std::move(made).value());
        }
        if (!data_items.empty()) target["dataItems"] = data_items;
        else target.erase("dataItems");
        if (!configs.empty()) target["configs"] = configs;
        else target.erase("configs");
        if (!components.empty()) target["components"] = components;
        else target.erase("components");
        return ok_result();
    }

    Result<Json> component(const ProbeComponent& c, Place parent) {
        std::string type;
        Place place = parent == Place::axis || parent == Place::in_axis ? Place::in_axis : Place::other;
        bool rotary = false;
        std::string description = c.description;
        if (c.element == "Linear" || c.element == "Rotary") {
            type = "AXIS";
            place = Place::axis;
            rotary = c.element == "Rotary";
        } else if (c.element == "Controller") {
            type = "CONTROLLER";
            place = Place::controller;
        } else {
            for (std::size_t i = 0; i < md::component_row_count() && type.empty(); ++i)
                if (md::component_row(i).element == c.element) type = std::string(md::component_row(i).type);
            if (type.empty()) {
                type = "COMPONENT";
                description = "MTConnect " + c.element + (description.empty() ? "" : ": " + description);
                out.unmatched.push_back({c.id, "component " + c.element, "COMPONENT (named in its description)"});
            }
        }
        const std::string id = unique(nclink_id(c.id));
        Json j = {{"id", id}, {"name", c.name.empty() ? id : c.name}, {"type", type}};
        if (!description.empty()) j["description"] = description;
        Json configs = Json::array();
        if (type == "AXIS")
            configs.push_back(Json{{"id", unique(id + "_category")},
                                   {"name", "axis kind"},
                                   {"type", "CATAGORY"},
                                   {"value", rotary ? "rotary" : "linear"}});
        description_configs(c, id, configs);
        if (!configs.empty()) j["configs"] = configs;
        if (auto r = fill(c, place, rotary, j); !r) return std::move(r).error();
        return j;
    }
};

Json Builder::fixed_value(const ItemBinding& b, const std::string& text) {
    Json v = nullptr;
    switch (b.rule) {
        case ValueRule::number: {
            char* end = nullptr;
            const double d = std::strtod(text.c_str(), &end);
            v = end != text.c_str() && *end == '\0' ? Json((d - b.offset) / b.scale) : Json(text);
            break;
        }
        case ValueRule::integer:
            v = !text.empty() && text.find_first_not_of("-0123456789") == std::string::npos ? Json(std::stoll(text)) : Json(text);
            break;
        case ValueRule::json: {
            Json parsed = Json::parse(text, nullptr, false);
            v = parsed.is_discarded() ? Json(text) : parsed;
            break;
        }
        case ValueRule::boolean: v = text == "true" ? Json(true) : text == "false" ? Json(false) : Json(text); break;
        case ValueRule::words: {
            v = text;
            for (const auto& [mt, word] : b.words)
                if (mt == text) v = word;
            break;
        }
        default: v = text;
    }
    return v;
}

}  // namespace

const ItemBinding* ReverseModel::find_mt(std::string_view id) const {
    const auto it = by_mt_id.find(std::string(id));
    return it == by_mt_id.end() ? nullptr : &items[it->second];
}
const ItemBinding* ReverseModel::find_shdr(std::string_view key) const {
    const auto it = by_shdr_key.find(std::string(key));
    return it == by_shdr_key.end() ? nullptr : &items[it->second];
}
const ItemBinding* ReverseModel::find_nclink(std::string_view id) const {
    const auto it = by_nclink_id.find(std::string(id));
    return it == by_nclink_id.end() ? nullptr : &items[it->second];
}

Result<ReverseModel> reverse_map(const ProbeDocument& probe, const ReverseOptions& options) {
    const ProbeComponent* device = find_device(probe, options.device);
    if (!device) return make_error(ErrorCode::node_not_exists, "probe: no Device with uuid, name or id '" + options.device + "'");
    ReverseModel out;
    Builder b{*device, out, {}, {}, options.min_sample_interval_ms, {}};
    // nclink-bridge prefixes every id of a device with its uuid (docs/mapping.md
    // "Identifier contract"): taken off again when every DataItem carries it.
    if (!device->uuid.empty()) {
        const std::string prefix = mtconnect_id(device->uuid) + ".";
        bool all = true;
        std::function<void(const ProbeComponent&)> check = [&](const ProbeComponent& c) {
            for (const auto& i : c.items) all = all && i.id.compare(0, prefix.size(), prefix) == 0;
            for (const auto& s : c.components) check(s);
        };
        check(*device);
        if (all) b.prefix = prefix;
    }
    out.dev_uuid = device->uuid.empty() ? device->id : device->uuid;
    out.mt_device = device->name.empty() ? device->id : device->name;
    out.instance_id = probe.instance_id;
    const std::string device_id = b.unique(b.nclink_id(device->id));
    Json dev = {{"id", device_id},
                {"name", device->name.empty() ? device_id : device->name},
                {"type", "MACHINE"},
                {"guid", out.dev_uuid},
                {"version", options.version}};
    dev["description"] = device->description.empty() ? "MTConnect device " + out.mt_device : device->description;
    Json configs = Json::array();
    b.description_configs(*device, device_id, configs);
    if (!configs.empty()) dev["configs"] = configs;
    if (auto r = b.fill(*device, Place::device, false, dev); !r) return std::move(r).error();
    // Sample channels from the sampleRates (A.4 h read back), fastest first.
    for (const auto& [interval, members] : b.by_interval) {
        Json ids = Json::array();
        for (const auto& id : members) ids.push_back(Json{{"id", id}});
        const std::string ms = std::to_string(interval);
        dev["configs"].push_back(Json{{"id", b.unique("mt_sample_" + ms + "ms")},
                                      {"name", "MTConnect samples every " + ms + " ms"},
                                      {"type", "SAMPLE_CHANNEL"},
                                      {"sampleInterval", interval},
                                      {"uploadInterval", std::max(1000, interval)},
                                      {"ids", ids}});
    }
    out.model = Json{{"id", options.root_id},
                     {"name", "MTConnect agent " + (probe.instance_id.empty() ? std::string() : "instance " + probe.instance_id)},
                     {"type", "NC_LINK_ROOT"},
                     {"description", "Generated by nclink from an MTConnect probe (GB/T 39561.3 appendix A read in reverse)"},
                     {"version", "1.0.0"},
                     {"devices", Json::array({dev})}};
    return out;
}

}  // namespace nclink::mtconnect
