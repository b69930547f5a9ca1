// Value vocabularies follow GB/T 41970-2022 tables 10 and 12-16; ranges are
// what a small machining centre shows (docs/simulator.md lists them).
#include "value_generators.hpp"

#include "sim_random.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <utility>

namespace nclink::sim {

namespace {

struct NumberSpec {
    std::string_view type;
    double lo;
    double hi;
    double period;
    int decimals;
};

// Table 10 physical quantities and table 13 numbers that drift.
constexpr std::array<NumberSpec, 29> drifting_numbers{{
    {"ACCELERATION", 0, 3000, 3, 1},
    {"ANGLE", 0, 6.2832, 8, 4},
    {"ANGULAR_ACCELERATION", 0, 50, 3, 3},
    {"ANGULAR_VELOCITY", 0, 60, 5, 3},
    {"CONCENTRATION", 0.02, 0.08, 60, 4},
    {"CONDUCTIVITY", 0.5, 5, 60, 3},
    {"CURRENT", 0, 20, 4, 2},
    {"DISPLACEMENT", 0, 500, 10, 3},
    {"FLOW", 0, 2, 20, 3},
    {"FREQUENCY", 0, 400, 10, 1},
    {"LENGTH", 0, 500, 30, 3},
    {"MASS", 0, 500, 60, 2},
    {"PERIOD", 0, 60, 30, 2},
    {"POSITION", -500, 500, 10, 3},
    {"POWER", 0, 15000, 5, 0},
    {"POWER_FACTOR", 0.7, 0.99, 20, 3},
    {"PRESSURE", 400000, 700000, 30, 0},
    {"RESISTANCE", 0, 1000, 60, 1},
    {"ROTATION_SPEED", 0, 12000, 8, 0},
    {"SPEED", 0, 6000, 5, 1},
    {"TEMPERATURE", 20, 60, 60, 1},
    {"TORQUE", 0, 50, 5, 2},
    {"VISCOSITY", 0.01, 0.1, 60, 4},
    {"VOLT_AMPERE", 0, 20000, 5, 0},
    {"AXIS_LOAD", 0, 100, 4, 1},
    {"FEED_SPEED", 0, 100, 6, 2},
    {"SPINDLE_SPEED", 0, 12000, 8, 0},
    {"RESIDUAL", 0, 100, 30, 2},
    {"AXIS_BACKLASH", 0.002, 0.02, 600, 4},
}};

struct BoolSpec {
    std::string_view type;
    double p_true;
};

// Table 13 Booleans with how often each is typically true.
constexpr std::array<BoolSpec, 22> booleans{{
    {"AUTO_MODE", 0.8},         {"AXIS_TOREFPOINT", 0.95}, {"BLOCK_SKIP_MODE", 0.1},  {"COOLANT_ON", 0.6},
    {"CYCLE_START", 0.7},       {"DOOR_CLOSED", 0.9},      {"EDIT_MODE", 0.05},       {"EMG", 0.02},
    {"FEED_HOLD", 0.1},         {"HANDLE_MODE", 0.1},      {"INCREMENTAL_MODE", 0.1}, {"JOG_MODE", 0.1},
    {"LIGHTING_ON", 0.9},       {"LUBRICANT_ON", 0.5},     {"MACHINE_LOCKED", 0.02},  {"MDI_MODE", 0.1},
    {"MST_LOCKED", 0.02},       {"OPT_STOP_MODE", 0.1},    {"REF_MODE", 0.05},        {"RESET_MODE", 0.05},
    {"SINGLE_BLOCK_MODE", 0.1}, {"TOOL_CHANGING", 0.1},
}};

struct Alias {
    std::string_view from;
    std::string_view to;
};

// Deviations seen in deployed files (docs/wire.md "Model files in the wild").
constexpr std::array<Alias, 9> aliases{{
    {"SPDL_OVERRIDE", "SPINDLE_OVERRIDE"},
    {"SPDL_SPEED", "SPINDLE_SPEED"},
    {"SPDL_LOAD", "AXIS_LOAD"},
    {"TYPE", "CATAGORY"},
    {"CATEGORY", "CATAGORY"},
    {"NUMBER", "SERIAL_NUMBER"},
    {"FEED_RATE", "FEED_SPEED"},
    {"ALARM", "WARNING"},
    {"LOAD", "AXIS_LOAD"},
}};

bool ends_with(std::string_view s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}
bool contains(std::string_view s, std::string_view part) { return s.find(part) != std::string_view::npos; }

double round_to(double v, int decimals) {
    const double scale = std::pow(10.0, decimals);
    return std::round(v * scale) / scale;
}

Json number_json(double v, int decimals) {
    if (decimals <= 0) return static_cast<std::int64_t>(std::llround(v));
    return round_to(v, decimals);
}

Generator drift_gen(double lo, double hi, double period, int decimals) {
    Generator g;
    g.shape = Shape::drift;
    g.lo = lo;
    g.hi = hi;
    g.period = period;
    g.decimals = decimals;
    return g;
}

Generator choice_gen(std::vector<std::string> words, std::vector<double> weights, double period) {
    Generator g;
    g.shape = Shape::choice;
    g.words = std::move(words);
    g.weights = std::move(weights);
    g.period = period;
    return g;
}

Generator text_gen(std::string text) {
    Generator g;
    g.shape = Shape::text;
    g.words = {std::move(text)};
    return g;
}

Generator stepped_gen(double lo, double hi, double step, double period) {
    Generator g;
    g.shape = Shape::stepped;
    g.lo = lo;
    g.hi = hi;
    g.step = step;
    g.period = period;
    g.decimals = 0;
    return g;
}

Json coordinate_object(const std::string& name, Rng& rng) {
    return Json{{"name", name},
                {"x", round_to(rng.uniform(-400, -100), 3)},
                {"y", round_to(rng.uniform(-300, -50), 3)},
                {"z", round_to(rng.uniform(-450, -200), 3)}};
}

std::string coordinate_name(std::size_t i) {
    // G54..G59, then the extended work offsets G54.1 P1, P2, ...
    if (i < 6) return fmt::format("G{}", 54 + i);
    return fmt::format("G54.1 P{}", i - 5);
}

Json tool_param_object(std::size_t i, Rng& rng) {
    static constexpr std::array<std::string_view, 5> kinds{"end_mill", "drill", "face_mill", "ball_mill", "tap"};
    const auto kind = kinds[static_cast<std::size_t>(rng.integer(0, kinds.size() - 1))];
    const double radius = 0.5 * static_cast<double>(rng.integer(2, 50));
    const double max_time = 3600.0 * static_cast<double>(rng.integer(4, 20));
    const std::int64_t max_count = rng.integer(500, 5000);
    const double max_length = 1000.0 * static_cast<double>(rng.integer(50, 500));
    return Json{{"type", "mill"},
                {"id", fmt::format("T{:02}", i + 1)},
                {"name", fmt::format("{} D{:g}", kind, radius * 2)},
                {"kind", kind},
                {"radius", radius},
                {"length", round_to(rng.uniform(60, 180), 3)},
                {"time_usage", round_to(rng.uniform(0, max_time * 0.8), 1)},
                {"max_time_usage", max_time},
                {"count_usage", rng.integer(0, max_count * 8 / 10)},
                {"max_count_usage", max_count},
                {"length_process", round_to(rng.uniform(0, max_length * 0.8), 1)},
                {"max_length_process", max_length},
                {"radius_abaration", round_to(rng.uniform(-0.02, 0.02), 4)},
                {"length_abaration", round_to(rng.uniform(-0.05, 0.05), 4)}};
}

Json part_object(Rng& rng) {
    static constexpr std::array<std::string_view, 4> materials{"6061-T6", "S45C", "SUS304", "Ti-6Al-4V"};
    return Json{{"id", fmt::format("P-{:04}", rng.integer(1, 9999))},
                {"name", "housing"},
                {"material", materials[static_cast<std::size_t>(rng.integer(0, materials.size() - 1))]},
                {"length", round_to(rng.uniform(50, 300), 1)},
                {"width", round_to(rng.uniform(50, 200), 1)},
                {"height", round_to(rng.uniform(10, 100), 1)}};
}

constexpr std::array<std::string_view, 6> program_names{"O1000", "O1001", "O2000", "O3100", "O5002", "O8000"};

}  // namespace

std::string canonical_type(std::string_view type) {
    std::string upper(type);
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (const auto& a : aliases)
        if (upper == a.from) return std::string(a.to);
    return upper;
}

Json warning_object(const std::string& number, const std::string& text, std::int64_t emerge_time) {
    return Json{{"number", number}, {"text", text}, {"emerge_time", emerge_time}};
}

std::pair<std::string, std::string> sample_alarm(std::uint64_t pick) {
    static constexpr std::array<std::pair<std::string_view, std::string_view>, 8> catalogue{{
        {"1001", "X axis following error too large"},
        {"1002", "Y axis following error too large"},
        {"1003", "Z axis following error too large"},
        {"2010", "spindle overload"},
        {"3005", "coolant level low"},
        {"3012", "lubrication pressure low"},
        {"4001", "door opened during cycle"},
        {"5020", "tool life expired"},
    }};
    const auto& a = catalogue[pick % catalogue.size()];
    return {std::string(a.first), std::string(a.second)};
}

Generator make_generator(const ItemTraits& item, std::uint64_t seed, std::size_t list_size) {
    const std::string& t = item.canonical;
    Generator g;
    bool found = false;
    if (item.rotary && t == "POSITION") {
        g = drift_gen(0, 360, 10, 3);
        found = true;
    }
    for (const auto& n : drifting_numbers) {
        if (!found && t == n.type) {
            g = drift_gen(n.lo, n.hi, n.period, n.decimals);
            found = true;
            break;
        }
    }
    if (!found) {
        for (const auto& b : booleans) {
            if (t == b.type) {
                g.shape = Shape::boolean;
                g.p_true = b.p_true;
                g.period = 20;
                found = true;
                break;
            }
        }
    }
    if (!found) {
        found = true;
        if (ends_with(t, "_OVERRIDE")) {
            g.shape = Shape::override_pct;
            g.hi = 150;
            g.period = 30;
            g.decimals = 0;
        } else if (t == "ENERGY") {
            g.shape = Shape::ramp;
            g.base = 12000;
            g.rate = 0.002;  // kW.h per second: a 7.2 kW average draw
            g.decimals = 3;
        } else if (t == "PATH_LEFT_LENGTH") {
            g.shape = Shape::sawtooth;
            g.lo = 0;
            g.hi = 500;
            g.period = 45;
        } else if (t == "PROGRAM_NUMBER") {
            g = stepped_gen(1000, 9999, 1, 120);
        } else if (t == "TOOL_NUMBER" || t == "TOOL_POSITION") {
            g = stepped_gen(1, 24, 1, 60);
        } else if (t == "SERIAL_NUMBER" || t == "UPPER_LIMIT" || t == "COMPACITY") {
            g.shape = Shape::constant;
            g.decimals = 0;
            g.lo = t == "COMPACITY" ? 24 : t == "UPPER_LIMIT" ? 10000 : 1;
            g.hi = t == "SERIAL_NUMBER" ? 99999 : g.lo;
        } else if (t == "PART_COUNT" || ends_with(t, "_COUNT")) {
            g.shape = Shape::counter;
            g.period = 90;
            g.base = 0;
        } else if (t == "LINE_NUMBER") {
            g.shape = Shape::line_number;
            g.period = 120;
        } else if (t == "STATUS") {
            g = choice_gen({"running", "free", "holding"}, {6, 3, 1}, 30);
        } else if (t == "WORK_MODE") {
            g = choice_gen({"auto", "manual"}, {4, 1}, 120);
        } else if (t == "SPINDLE_MODE" || t == "CHIP_REMOVAL") {
            g = choice_gen({"forward", "stop", "reverse"}, {6, 3, 1}, 20);
        } else if (t == "FIXTURE_MODE") {
            g = choice_gen({"tight", "loose"}, {5, 1}, 60);
        } else if (t == "TOOL_CHANGE") {
            g = choice_gen({"auto", "manual"}, {}, 1e9);
        } else if (t == "USER_ROLE") {
            g = choice_gen({"operator", "manager", "machine_manufacturer", "cnc_manufacturer", "system_manager"}, {}, 1e9);
        } else if (t == "CATAGORY") {
            // Table 16: the value depends on what the item describes.
            if (item.parent_type == "AXIS") g = choice_gen({"linear", "rotary"}, {3, 1}, 1e9);
            else if (item.parent_type == "MACHINE") g = choice_gen({"milling", "lathe", "grinder", "planer", "other"}, {}, 1e9);
            else g = text_gen("other");
        } else if (t == "MANUFACTURER") {
            g = text_gen("nclink-sim");
        } else if (t == "MODEL") {
            g = text_gen("SIM-" + std::to_string(1000 + mix64(seed ^ hash_text(item.id)) % 9000));
        } else if (t == "NAME") {
            g = text_gen(item.name.empty() ? item.id : item.name);
        } else if (t == "VERSION") {
            g = text_gen("1.0.0");
        } else if (t == "IP") {
            g = text_gen("192.168.1." + std::to_string(10 + mix64(seed ^ hash_text(item.id)) % 200));
        } else if (t == "CREATOR") {
            g = text_gen("nclink");
        } else if (t == "CREATE_TIME") {
            g = text_gen("2024-01-01T08:00:00Z");
        } else if (t == "CONSOLE") {
            g = text_gen("console-1");
        } else if (t == "FILE") {
            g = text_gen("/prog/O1000.nc");
        } else if (t == "SITE") {
            g = choice_gen({"site-01", "site-02", "site-03", "site-04"}, {}, 60);
        } else if (t == "PROGRAM_MODE") {
            g = choice_gen({"memory", "mdi", "dnc"}, {6, 1, 1}, 300);
        } else if (t == "PROGRAM" || t == "SUBPROGRAM") {
            std::vector<std::string> words;
            for (auto p : program_names) words.emplace_back(t == "PROGRAM" ? std::string(p) : "O9" + std::string(p.substr(2)));
            g = choice_gen(std::move(words), {}, 300);
        } else if (t == "WARNING") {
            g.shape = Shape::warning;
            g.period = 60;
            g.p_true = 0.25;
        } else if (t == "COORDINATE" || t == "TOOL_PARAM" || t == "PART" || t == "TOOL" || t == "PARAMETER" || t == "VARIABLE" ||
                   t == "SHELF_UNIT") {
            // Composite types given without a datatype: a fixed value of the
            // table-12/13/14 shape.
            g.shape = Shape::object;
            Rng rng(mix64(seed ^ hash_text(item.id)));
            if (t == "COORDINATE") g.fixed = coordinate_object("G54", rng);
            else if (t == "TOOL_PARAM") g.fixed = tool_param_object(0, rng);
            else if (t == "PART") g.fixed = part_object(rng);
            else {
                ItemTraits as_collection = item;
                as_collection.kind = t == "PARAMETER" ? DataKind::dict : DataKind::list;
                g.fixed = make_collection(as_collection, seed, list_size);
            }
        } else if (ends_with(t, "_SPEED")) {
            g = drift_gen(0, 6000, 5, 1);
        } else if (ends_with(t, "_MODE") || ends_with(t, "_ON") || ends_with(t, "_LOCKED") || ends_with(t, "_CLOSED")) {
            g.shape = Shape::boolean;
            g.p_true = 0.3;
            g.period = 20;
        } else if (contains(t, "TEMP")) {
            g = drift_gen(20, 60, 60, 1);
        } else if (ends_with(t, "_NAME") || ends_with(t, "_ID")) {
            g = text_gen(item.name.empty() ? item.id : item.name);
        } else {
            // Unknown: a bounded random drift, the safest guess for a sensor.
            g = drift_gen(0, 100, 10, 3);
        }
    }
    g.stream = mix64(seed ^ hash_text(item.id));
    return g;
}

Json generate(const Generator& g, double t, std::int64_t wall_ms) {
    switch (g.shape) {
        case Shape::drift: return number_json(g.lo + (g.hi - g.lo) * drift(g.stream, t, g.period), g.decimals);
        case Shape::stepped: {
            const double slots = std::floor((g.hi - g.lo) / g.step) + 1;
            const double u = lattice(g.stream, static_cast<std::int64_t>(std::floor(t / g.period)));
            return number_json(g.lo + g.step * std::floor(u * slots), g.decimals);
        }
        case Shape::override_pct: {
            const auto k = static_cast<std::int64_t>(std::floor(t / g.period));
            if (lattice(g.stream, k) < 0.6) return std::int64_t{100};
            const double u = lattice(mix64(g.stream), k);
            return static_cast<std::int64_t>(10 * std::floor(u * (g.hi / 10 + 1)));
        }
        case Shape::constant: return number_json(g.lo + std::floor(unit(g.stream) * (g.hi - g.lo + 1)), 0);
        case Shape::ramp: return number_json(g.base + g.rate * (t - g.origin), g.decimals);
        case Shape::sawtooth: {
            const double phase = std::fmod(t, g.period) / g.period;
            return number_json(g.hi - (g.hi - g.lo) * phase, 3);
        }
        case Shape::counter: {
            const double n = g.base + std::floor(std::max(0.0, t - g.origin) / g.period);
            return std::to_string(static_cast<std::int64_t>(n));
        }
        case Shape::line_number: {
            const double phase = std::fmod(t, g.period) / g.period;
            return std::to_string(10 * (1 + static_cast<std::int64_t>(phase * 200)));
        }
        case Shape::boolean: return lattice(g.stream, static_cast<std::int64_t>(std::floor(t / g.period))) < g.p_true;
        case Shape::choice: {
            if (g.words.empty()) return "";
            const double u = lattice(g.stream, static_cast<std::int64_t>(std::floor(t / g.period)));
            if (g.weights.size() != g.words.size())
                return g.words[std::min(g.words.size() - 1, static_cast<std::size_t>(u * static_cast<double>(g.words.size())))];
            double total = 0;
            for (double w : g.weights) total += w;
            double acc = 0;
            for (std::size_t i = 0; i < g.words.size(); ++i) {
                acc += g.weights[i] / total;
                if (u < acc) return g.words[i];
            }
            return g.words.back();
        }
        case Shape::text: return g.words.empty() ? std::string() : g.words[0];
        case Shape::warning: {
            // An alarm is active in some `period` slots; it emerged at the slot start.
            const auto k = static_cast<std::int64_t>(std::floor(t / g.period));
            if (lattice(g.stream, k) >= g.p_true) return Json::object();
            const auto [number, text] = sample_alarm(hash_pair(g.stream, static_cast<std::uint64_t>(k)));
            const auto since_ms = static_cast<std::int64_t>((t - static_cast<double>(k) * g.period) * 1000.0);
            return warning_object(number, text, wall_ms - since_ms);
        }
        case Shape::object: return g.fixed;
    }
    return nullptr;
}

Json make_collection(const ItemTraits& item, std::uint64_t seed, std::size_t size) {
    const std::string& t = item.canonical;
    Rng rng(mix64(seed ^ hash_text(item.id) ^ 0x5eedULL));
    const bool dict = item.kind == DataKind::dict;
    Json out = dict ? Json::object() : Json::array();
    auto put = [&](std::size_t i, const std::string& key, Json v) {
        (void)i;
        if (dict) out[key] = std::move(v);
        else out.push_back(std::move(v));
    };
    // Scalar element types reuse the single-value generator at spread-out times.
    ItemTraits element = item;
    element.kind = DataKind::single;
    if (t == "TOOL") element.canonical = "TOOL_PARAM";
    if (t == "VARIABLE" || t == "PARAMETER") element.canonical = "UNKNOWN_NUMBER";
    if (t == "SHELF_UNIT") element.canonical = "SHELF";
    const Generator scalar = make_generator(element, seed, size);
    for (std::size_t i = 0; i < size; ++i) {
        if (t == "TOOL" || t == "TOOL_PARAM") {
            put(i, fmt::format("T{:02}", i + 1), tool_param_object(i, rng));
        } else if (t == "COORDINATE") {
            const std::string name = coordinate_name(i);
            put(i, name, coordinate_object(name, rng));
        } else if (t == "PARAMETER") {
            // Machine parameters: integers and decimals, as a control lists them.
            Json v = (i % 3 == 0) ? Json(rng.integer(0, 10000)) : Json(round_to(rng.uniform(0, 1000), 3));
            put(i, fmt::format("P{:04}", i), std::move(v));
        } else if (t == "PROGRAM" || t == "SUBPROGRAM") {
            const std::string prefix = t == "PROGRAM" ? "O" : "O9";
            put(i, fmt::format("CH{}", i), fmt::format("{}{:03}", prefix, rng.integer(0, 999)));
        } else if (t == "SHELF_UNIT") {
            const bool occupied = rng.uniform(0, 1) < 0.6;
            put(i, fmt::format("S{:02}", i + 1),
                Json{{"id", fmt::format("S{:02}", i + 1)},
                     {"occupied", occupied},
                     {"part", occupied ? fmt::format("P-{:04}", rng.integer(1, 9999)) : std::string()}});
        } else if (t == "PART") {
            put(i, fmt::format("part_{:02}", i), part_object(rng));
        } else if (t == "WARNING") {
            const auto [number, text] = sample_alarm(rng.next());
            put(i, number + "_" + std::to_string(i), warning_object(number, text, 1'700'000'000'000 - rng.integer(0, 86'400'000)));
        } else {
            put(i, fmt::format("{}_{}", item.id, i), generate(scalar, 3.7 * static_cast<double>(i), 1'700'000'000'000));
        }
    }
    return out;
}

}  // namespace nclink::sim
