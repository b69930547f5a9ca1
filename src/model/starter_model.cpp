// Starter models (include/nclink/starter_model.hpp). The vocabulary is
// chapter 7's: a MACHINE device (table 7) with a CATAGORY of table 16,
// AXIS components numbered per table 9 (spindles as axis S, docs/model.md),
// CONTROLLER components (table 8) with STATUS/WORK_MODE (table 15),
// PROGRAM, LINE_NUMBER, PART_COUNT, FEED_OVERRIDE (table 13), WARNING
// (table 14), and one SAMPLE_CHANNEL (6.2.3).
#include <nclink/starter_model.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <regex>
#include <set>

namespace nclink {
namespace {

std::string lower(std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

Json item(const std::string& id, const std::string& name, const std::string& type, const char* units = nullptr) {
    Json j{{"id", id}, {"name", name}, {"type", type}};
    if (units) j["units"] = units;
    return j;
}

Json fixed(const std::string& id, const std::string& name, const std::string& type, Json value) {
    return Json{{"id", id}, {"name", name}, {"type", type}, {"value", std::move(value)}};
}

bool rotary(const std::string& axis) { return axis[0] == 'A' || axis[0] == 'B' || axis[0] == 'C'; }

}  // namespace

Result<MachineKind> machine_kind_from_string(const std::string& text) {
    const std::string t = lower(text);
    if (t == "lathe") return MachineKind::lathe;
    if (t == "machining-center" || t == "machining_center" || t == "mill" || t == "mc") return MachineKind::machining_center;
    if (t == "generic") return MachineKind::generic;
    return make_error(ErrorCode::value_type, fmt::format("unknown machine kind '{}': lathe, machining-center or generic", text));
}

Result<Json> make_starter_model(const StarterModelOptions& o) {
    const bool lathe = o.kind == MachineKind::lathe, mc = o.kind == MachineKind::machining_center;
    std::vector<std::string> axes = o.axes;
    if (axes.empty())
        axes = lathe ? std::vector<std::string>{"X", "Z"}
               : mc  ? std::vector<std::string>{"X", "Y", "Z"}
                     : std::vector<std::string>{};
    const int spindles = o.spindles >= 0 ? o.spindles : (o.kind == MachineKind::generic ? 0 : 1);
    const int channels = o.channels >= 0 ? o.channels : (o.kind == MachineKind::generic ? 0 : 1);
    if (spindles > 9 || channels > 9)
        return make_error(ErrorCode::value_type, "at most 9 spindles and 9 channels in a starter model");
    if (o.id.empty() || o.id.find_first_of("/+# ") != std::string::npos)
        return make_error(ErrorCode::value_type, fmt::format("device id '{}' must be non-empty, without / + # or spaces", o.id));
    // Table 9: linear X Y Z, rotary A B C, swivel U V W, each optionally numbered (X1...).
    static const std::regex axis_number("[XYZABCUVW][0-9]*");
    std::set<std::string> seen;
    for (auto& a : axes) {
        for (char& c : a) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (!std::regex_match(a, axis_number))
            return make_error(
                ErrorCode::value_type,
                fmt::format("axis '{}' is not a table 9 number (X Y Z, A B C, U V W, optionally followed by digits)", a));
        if (!seen.insert(a).second) return make_error(ErrorCode::value_type, fmt::format("axis '{}' given twice", a));
    }

    const std::string kind_name = lathe ? "lathe" : mc ? "machining center" : "machine";
    const std::string name = o.name.empty() ? fmt::format("{} {}", o.manufacturer, kind_name) : o.name;
    Json configs = Json::array({
        fixed("machine_category", "Machine kind", "CATAGORY",
              lathe ? "lathe"
              : mc  ? "milling"
                    : "other"),
        fixed("manufacturer", "Machine builder", "MANUFACTURER", o.manufacturer),
        fixed("machine_model", "Machine model", "MODEL", "MODEL-1"),
    });
    Json components = Json::array();
    Json sampled = Json::array();

    for (const auto& a : axes) {
        const std::string l = lower(a);
        const bool rot = rotary(a);
        Json data = Json::array({item(l + "_position", a + " actual position", rot ? "ANGLE" : "POSITION", rot ? "DEGREE" : "mm"),
                                 item(l + "_load", a + " drive load", "AXIS_LOAD", "PERCENT")});
        components.push_back(
            Json{{"id", "axis_" + l},
                 {"name", a + " axis"},
                 {"type", "AXIS"},
                 {"number", a},
                 {"configs", Json::array({fixed(l + "_category", a + " axis kind", "CATAGORY", rot ? "rotary" : "linear")})},
                 {"dataItems", data}});
        sampled.push_back(Json{{"id", l + "_position"}});
    }
    for (int s = 1; s <= spindles; ++s) {
        const std::string number = spindles == 1 ? "S" : fmt::format("S{}", s);
        const std::string p = spindles == 1 ? "spindle" : fmt::format("spindle{}", s);
        components.push_back(
            Json{{"id", p},
                 {"name", spindles == 1 ? std::string("Spindle") : fmt::format("Spindle {}", s)},
                 {"type", "AXIS"},
                 {"number", number},
                 {"description", "Spindle (an axis numbered S)"},
                 {"configs", Json::array({fixed(p + "_max_speed", "Spindle speed limit", "UPPER_LIMIT", lathe ? 4000 : 12000)})},
                 {"dataItems", Json::array({item(p + "_speed", "Spindle actual speed", "SPINDLE_SPEED", "r/min"),
                                            item(p + "_load", "Spindle load", "AXIS_LOAD", "PERCENT"),
                                            [&] {
                                                Json j = item(p + "_override", "Spindle override", "SPINDLE_OVERRIDE", "PERCENT");
                                                j["setable"] = true;
                                                return j;
                                            }(),
                                            item(p + "_mode", "Spindle direction", "SPINDLE_MODE")})}});
        sampled.push_back(Json{{"id", p + "_speed"}});
    }
    for (int c = 1; c <= channels; ++c) {
        const std::string sfx = channels == 1 ? "" : fmt::format("_{}", c);
        Json feed = item("feed_override" + sfx, "Feed override", "FEED_OVERRIDE", "PERCENT");
        feed["setable"] = true;
        components.push_back(Json{
            {"id", "controller" + sfx},
            {"name", channels == 1 ? std::string("CNC controller") : fmt::format("CNC channel {}", c)},
            {"type", "CONTROLLER"},
            {"configs", Json::array({fixed("cnc_model" + sfx, "CNC model", "MODEL", "CNC-1"),
                                     fixed("cnc_version" + sfx, "CNC software version", "VERSION", "1.0")})},
            {"dataItems",
             Json::array(
                 {item("status" + sfx, "Run status", "STATUS"), item("work_mode" + sfx, "Work mode", "WORK_MODE"),
                  item("program" + sfx, "Main program", "PROGRAM"), item("line_number" + sfx, "Program line", "LINE_NUMBER"),
                  item("part_count" + sfx, "Parts made", "PART_COUNT"), feed, item("alarm" + sfx, "Current alarm", "WARNING")})}});
        sampled.push_back(Json{{"id", "status" + sfx}});
    }
    Json device_items = Json::array();
    if (channels == 0) {
        // A machine without a CNC still says whether it runs.
        device_items.push_back(item("status", "Run status", "STATUS"));
        device_items.push_back(item("alarm", "Current alarm", "WARNING"));
        sampled.push_back(Json{{"id", "status"}});
    }
    configs.push_back(Json{{"id", "ch_main"},
                           {"name", "Machine state"},
                           {"type", "SAMPLE_CHANNEL"},
                           {"sampleInterval", o.sample_interval_ms},
                           {"uploadInterval", o.upload_interval_ms},
                           {"ids", sampled}});

    Json device{{"id", o.id},
                {"name", name},
                {"type", "MACHINE"},
                {"description", fmt::format("{} ({} axes, {} spindle(s), {} channel(s))", name, axes.size(), spindles, channels)},
                {"number", "0001"},
                {"guid", o.id + "-0001"},
                {"version", "1.0.0"},
                {"configs", configs}};
    if (!device_items.empty()) device["dataItems"] = device_items;
    if (!components.empty()) device["components"] = components;
    return Json{{"id", o.id + "-root"},
                {"name", name},
                {"type", "NC_LINK_ROOT"},
                {"description", "Starter model made by `nclink model new`: edit names, add what the machine has"},
                {"version", "1.0.0"},
                {"devices", Json::array({device})}};
}

}  // namespace nclink
