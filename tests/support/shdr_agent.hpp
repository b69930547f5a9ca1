// An MTConnect agent's reading of SHDR, for tests of what the bridge sends:
// given the Devices document the agent was started with (the bridge's
// /probe) and the SHDR text of its adapter connection (the bridge's SHDR
// port), what the agent's current value of every DataItem becomes.
//
// Written here from the SHDR adapter format as the MTConnect agent
// (mtconnect/cppagent, checked against 1.8.0.3 and 2.x) documents and
// behaves, not from its code:
//   - a line is `timestamp|key|value...`; a line starting with `*` is a
//     protocol command (`* PONG 10000`), not data;
//   - tokens are split at `|` and trimmed of white space; a token starting
//     with `"` runs to a `"` followed by `|` or the end of the line, and a
//     backslash in it escapes the next character (with the agent's
//     treatment of a quote that closes nothing, see tokens()); a `|` ending
//     the line gives one more, empty token;
//   - a key `device:item` is split at its first `:`; the device is found by
//     uuid, then by name (no device part: the first device); the DataItem of
//     that device by its `<Source>`, then its name, then its id;
//   - the tokens after the key fill the fields of the DataItem's kind in
//     order: SAMPLE value (a number; `x y z` for units ending in 3D;
//     sampleCount|sampleRate|values for TIME_SERIES), EVENT MESSAGE
//     nativeCode|value, EVENT ALARM code|nativeCode|severity|state|value,
//     other EVENTs value, CONDITION level|nativeCode|nativeSeverity|qualifier|value;
//     an empty token leaves its field unset; UNAVAILABLE (any case) as the
//     value or level makes the item unavailable, and so does a missing value;
//   - a line may carry several `key|value` pairs, but (SHDR version 1) once
//     an item has taken more than one value token the rest of the line is
//     ignored; an unknown key is skipped together with the token after it;
//   - a DataItem with a single Constraints/Value is constant: lines for it
//     are ignored and its value is that constant; every other item starts
//     UNAVAILABLE;
//   - a SAMPLE value that is not a number is refused (no observation);
//   - a SAMPLE whose DataItem has `nativeUnits` is taken to be in those
//     units and converted to `units` (the agent's default, ConversionRequired),
//     by the agent's own factors: INCH 25.4, FOOT 304.8, CENTIMETER 10,
//     DECIMETER 100, METER 1000, FAHRENHEIT 5/9 after subtracting 32, POUND
//     0.45359237, GRAM 0.001, RADIAN 57.2957795, MINUTE 60, HOUR 3600, any
//     other unit 1; `A/B` as A / B (`B^n` to the power n),
//     REVOLUTION/SECOND as 60, REVOLUTION/MINUTE unchanged; a unit without
//     `/` whose factor is 1 is unchanged unless it is KILO + `units` (1000).
//     The result is written with 15 significant digits.
// DATA_SET and TABLE representations (MTConnect 1.5 and 1.6) are not read:
// a 1.4 Devices document cannot declare them (docs/bridge.md "SHDR").
#pragma once

#include <libxml/parser.h>
#include <libxml/tree.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace nclink::test {

class ShdrAgent {
public:
    /// What the agent shows for one DataItem.
    struct Current {
        bool available = false;
        std::string value;             ///< the value's text (conditions: the last line's text)
        std::string native_code;       ///< MESSAGE, ALARM, CONDITION
        std::string level;             ///< CONDITION: normal, warning, fault
        std::set<std::string> active;  ///< CONDITION: native codes of active warnings/faults
    };

    /// `devices_xml`: an MTConnectDevices document. Throws std::runtime_error when it does not parse.
    explicit ShdrAgent(const std::string& devices_xml) { load(devices_xml); }

    /// Feeds SHDR text (whole lines; a partial last line waits for the rest).
    void feed(const std::string& text) {
        pending_ += text;
        std::size_t eol;
        while ((eol = pending_.find('\n')) != std::string::npos) {
            std::string line = pending_.substr(0, eol);
            pending_.erase(0, eol + 1);
            if (!line.empty() && line.back() == '\r') line.pop_back();
            this->line(line);
        }
    }

    /// By DataItem id; nullptr for an id the Devices document does not have.
    const Current* current(const std::string& id) const {
        auto it = items_.find(id);
        return it == items_.end() ? nullptr : &it->second.current;
    }
    /// Every DataItem id of the Devices document.
    std::vector<std::string> ids() const {
        std::vector<std::string> out;
        for (const auto& [id, item] : items_) out.push_back(id);
        return out;
    }
    /// Keys that named no DataItem, and values the agent refused.
    const std::vector<std::string>& problems() const noexcept { return problems_; }

private:
    struct Item {
        std::string id, name, source, category, type, units, native_units, representation;
        std::optional<std::string> constant;
        Current current;
    };
    struct Device {
        std::string uuid, name;
        std::vector<std::string> ids;
    };

    static std::string prop(const xmlNode* n, const char* name) {
        xmlChar* v = xmlGetProp(n, reinterpret_cast<const xmlChar*>(name));
        if (!v) return {};
        std::string out(reinterpret_cast<const char*>(v));
        xmlFree(v);
        return out;
    }
    static std::string text(const xmlNode* n) {
        xmlChar* v = xmlNodeGetContent(n);
        if (!v) return {};
        std::string out(reinterpret_cast<const char*>(v));
        xmlFree(v);
        return out;
    }
    static bool named(const xmlNode* n, const char* name) {
        return n->type == XML_ELEMENT_NODE && xmlStrcmp(n->name, reinterpret_cast<const xmlChar*>(name)) == 0;
    }

    void load(const std::string& xml) {
        std::unique_ptr<xmlDoc, void (*)(xmlDocPtr)> doc(
            xmlReadMemory(xml.data(), static_cast<int>(xml.size()), "devices.xml", "UTF-8",
                          XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING),
            xmlFreeDoc);
        if (!doc) throw std::runtime_error("the Devices document does not parse");
        walk(xmlDocGetRootElement(doc.get()), nullptr);
    }

    void walk(const xmlNode* node, Device* device) {
        for (; node; node = node->next) {
            if (node->type != XML_ELEMENT_NODE) continue;
            if (named(node, "Device")) {
                devices_.push_back(Device{prop(node, "uuid"), prop(node, "name"), {}});
                walk(node->children, &devices_.back());
                continue;
            }
            if (named(node, "DataItem") && device) {
                Item item;
                item.id = prop(node, "id");
                item.name = prop(node, "name");
                item.category = prop(node, "category");
                item.type = prop(node, "type");
                item.units = prop(node, "units");
                item.native_units = prop(node, "nativeUnits");
                item.representation = prop(node, "representation");
                std::vector<std::string> values;
                for (const xmlNode* c = node->children; c; c = c->next) {
                    if (named(c, "Source")) item.source = text(c);
                    if (named(c, "Constraints"))
                        for (const xmlNode* v = c->children; v; v = v->next)
                            if (named(v, "Value")) values.push_back(text(v));
                }
                if (values.size() == 1) {
                    item.constant = values.front();
                    item.current.available = true;
                    item.current.value = values.front();
                }
                device->ids.push_back(item.id);
                items_[item.id] = std::move(item);
                continue;
            }
            walk(node->children, device);
        }
    }

    // The agent's tokenizer, quirks included, so a value it would cut or
    // change shows here too: a token starting with '"' ends at a '"'
    // followed (after spaces) by '|' or the end of the line; a backslash in
    // it drops itself and keeps the next character; a '|' ends it anyway.
    // When no such closing quote comes, a token with a backslash is read
    // again as plain text from its quote to the next '|', and one without
    // loses its opening quote and ends at the next '|' or at a '"' not
    // closing it, after which the rest is read as a new token.
    static std::vector<std::string> tokens(const std::string& line) {
        std::vector<std::string> out;
        std::size_t i = 0;
        const std::size_t n = line.size();
        auto rtrim = [](std::string s) {
            while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
            return s;
        };
        while (i < n) {
            while (i < n && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            if (i >= n) break;
            std::string token;
            std::size_t cp = i;
            if (line[i] == '"') {
                const std::size_t orig = i;
                cp = i + 1;
                bool copied = false, closed = false;
                while (cp < n) {
                    const char c = line[cp];
                    if (c == '\\') {
                        copied = true;
                        ++cp;  // the backslash goes, the next character stays
                        if (cp < n) token += line[cp++];
                        continue;
                    }
                    if (c == '|') break;
                    if (c == '"') {
                        std::size_t k = cp + 1;
                        while (k < n && std::isspace(static_cast<unsigned char>(line[k]))) ++k;
                        if (k == n || line[k] == '|') {
                            closed = true;
                            cp = k;
                            break;
                        }
                        break;  // a quote that closes nothing: the token ends here
                    }
                    token += c;
                    ++cp;
                }
                if (!closed && copied) {
                    cp = orig;
                    while (cp < n && line[cp] != '|') ++cp;
                    token = line.substr(orig, cp - orig);
                }
                out.push_back(rtrim(token));
            } else {
                while (cp < n && line[cp] != '|') ++cp;
                out.push_back(rtrim(line.substr(i, cp - i)));
            }
            if (cp < n && line[cp] == '|' && cp + 1 == n) out.emplace_back();
            i = cp < n ? cp + 1 : cp;
        }
        return out;
    }

    static double unit_factor(const std::string& unit, double* offset) {
        static const std::map<std::string, double> factors = {{"INCH", 25.4},        {"FOOT", 304.8},   {"CENTIMETER", 10.0},
                                                              {"DECIMETER", 100.0},  {"METER", 1000.0}, {"FAHRENHEIT", 5.0 / 9},
                                                              {"POUND", 0.45359237}, {"GRAM", 0.001},   {"RADIAN", 57.2957795},
                                                              {"MINUTE", 60.0},      {"HOUR", 3600.0}};
        auto it = factors.find(unit);
        if (it == factors.end()) return 1.0;
        if (unit == "FAHRENHEIT" && offset) *offset = -32.0;
        return it->second;
    }

    /// value -> (value + offset) * factor from nativeUnits to units; nullopt: left as it is.
    static std::optional<std::pair<double, double>> conversion(const Item& item) {
        if (item.native_units.empty()) return std::nullopt;
        std::string native = item.native_units;
        double offset = 0;
        const auto slash = native.find('/');
        if (slash == std::string::npos) {
            if (auto d3 = native.find("_3D"); d3 != std::string::npos) native.erase(d3);
            const double f = unit_factor(native, &offset);
            if (f != 1.0) return std::make_pair(f, offset);
            if (native.compare(0, 4, "KILO") == 0 && native.substr(4) == item.units) return std::make_pair(1000.0, 0.0);
            return std::nullopt;
        }
        if (native == "REVOLUTION/MINUTE") return std::nullopt;
        const std::string num = native.substr(0, slash), den = native.substr(slash + 1);
        if (num == "REVOLUTION" && den == "SECOND") return std::make_pair(60.0, 0.0);
        const auto caret = den.find('^');
        if (caret == std::string::npos) return std::make_pair(unit_factor(num, nullptr) / unit_factor(den, nullptr), 0.0);
        const double power = std::atof(den.c_str() + caret + 1);
        return std::make_pair(unit_factor(num, nullptr) / std::pow(unit_factor(den.substr(0, caret), nullptr), power), 0.0);
    }

    static bool unavailable(const std::string& s) {
        std::string up = s;
        for (auto& c : up) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        return up == "UNAVAILABLE";
    }

    Item* find(const std::string& key) {
        std::string device_part, item_part = key;
        if (auto c = key.find(':'); c != std::string::npos) {
            device_part = key.substr(0, c);
            item_part = key.substr(c + 1);
        }
        const Device* device = nullptr;
        if (device_part.empty()) {
            device = devices_.empty() ? nullptr : &devices_.front();
        } else {
            for (const auto& d : devices_)
                if (d.uuid == device_part) device = &d;
            if (!device)
                for (const auto& d : devices_)
                    if (d.name == device_part) device = &d;
        }
        if (!device) return nullptr;
        for (std::string Item::*field : {&Item::source, &Item::name, &Item::id})
            for (const auto& id : device->ids) {
                Item& item = items_.at(id);
                if (!(item.*field).empty() && item.*field == item_part) return &item;
            }
        return nullptr;
    }

    void line(const std::string& line) {
        if (line.empty() || line[0] == '*') return;
        const auto t = tokens(line);
        std::size_t i = 1;  // t[0] is the timestamp
        while (i < t.size()) {
            const std::size_t start = i;
            Item* item = find(t[i++]);
            if (!item) {
                problems_.push_back("no data item for key '" + t[start] + "'");
                ++i;  // and its value
                continue;
            }
            std::vector<std::string> fields;
            if (item->category == "SAMPLE") {
                fields = item->representation == "TIME_SERIES" ? std::vector<std::string>{"sampleCount", "sampleRate", "VALUE"}
                                                               : std::vector<std::string>{"VALUE"};
            } else if (item->category == "CONDITION") {
                fields = {"level", "nativeCode", "nativeSeverity", "qualifier", "VALUE"};
            } else if (item->type == "MESSAGE") {
                fields = {"nativeCode", "VALUE"};
            } else if (item->type == "ALARM") {
                fields = {"code", "nativeCode", "severity", "state", "VALUE"};
            } else if (item->type == "ASSET_CHANGED" || item->type == "ASSET_REMOVED") {
                fields = {"assetType", "VALUE"};
            } else {
                fields = {"VALUE"};
            }
            std::map<std::string, std::string> set;
            bool is_unavailable = false;
            for (const auto& field : fields) {
                if (i >= t.size()) break;
                const std::string& token = t[i++];
                if ((field == "VALUE" || field == "level") && unavailable(token)) {
                    is_unavailable = true;
                    continue;
                }
                if (token.empty()) continue;
                set[field] = token;
            }
            apply(*item, set, is_unavailable);
            if (i - start > 2) break;  // SHDR version 1: no more pairs after a multi-field item
        }
    }

    void apply(Item& item, const std::map<std::string, std::string>& set, bool is_unavailable) {
        if (item.constant) return;
        Current& c = item.current;
        auto value = set.find("VALUE");
        if (item.category == "CONDITION") {
            auto level = set.find("level");
            if (is_unavailable || level == set.end()) {
                c = Current{};
                return;
            }
            std::string l = level->second;
            for (auto& ch : l) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            auto code = set.find("nativeCode");
            c.available = true;
            c.level = l;
            c.native_code = code == set.end() ? "" : code->second;
            c.value = value == set.end() ? "" : value->second;
            if (l == "normal") {
                if (c.native_code.empty()) c.active.clear();
                else c.active.erase(c.native_code);
            } else {
                c.active.insert(c.native_code);
            }
            return;
        }
        if (value != set.end() && item.category == "SAMPLE" && item.representation != "TIME_SERIES") {
            // A number (three for 3D units); anything else is refused.
            std::istringstream in(value->second);
            double d = 0;
            int count = 0;
            while (in >> d) ++count;
            const bool three_d = item.units.size() >= 2 && item.units.compare(item.units.size() - 2, 2, "3D") == 0;
            if (!in.eof() || count != (three_d ? 3 : 1)) {
                problems_.push_back("not a number for " + item.id + ": '" + value->second + "'");
                return;
            }
            if (const auto conv = conversion(item)) {
                std::istringstream numbers(value->second);
                std::string converted;
                while (numbers >> d) {
                    char buf[64];
                    std::snprintf(buf, sizeof buf, "%.15g", (d + conv->second) * conv->first);
                    converted += (converted.empty() ? "" : " ") + std::string(buf);
                }
                c.available = true;
                c.value = converted;
                c.native_code.clear();
                return;
            }
        }
        if (is_unavailable || value == set.end()) {
            c = Current{};
            return;
        }
        c.available = true;
        c.value = value->second;
        auto code = set.find("nativeCode");
        c.native_code = code == set.end() ? "" : code->second;
    }

    std::vector<Device> devices_;
    std::map<std::string, Item> items_;
    std::vector<std::string> problems_;
    std::string pending_;
};

}  // namespace nclink::test
