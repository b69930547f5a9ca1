#include "modbus/modbus_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

namespace nclink::modbus {
namespace {

struct NamedTable {
    const char* name;
    Table table;
};
// The names of the Modbus application protocol, and the short forms PLC
// documentation uses.
constexpr NamedTable table_names[] = {
    {"coil", Table::coil},
    {"discrete_input", Table::discrete_input},
    {"discrete", Table::discrete_input},
    {"holding_register", Table::holding_register},
    {"holding", Table::holding_register},
    {"input_register", Table::input_register},
    {"input", Table::input_register},
};

struct NamedType {
    const char* name;
    RegType type;
};
constexpr NamedType type_names[] = {
    {"bool", RegType::boolean},  {"int16", RegType::int16}, {"uint16", RegType::uint16},   {"int32", RegType::int32},
    {"uint32", RegType::uint32}, {"int64", RegType::int64}, {"float32", RegType::float32}, {"float64", RegType::float64},
};

bool is_bit_table(Table t) { return t == Table::coil || t == Table::discrete_input; }

Error config_error(const std::string& where, const std::string& what) {
    return make_error(ErrorCode::value_type, "modbus driver configuration: " + where + ": " + what);
}

template <typename T>
Result<T> number_in(const Json& j, const std::string& where, T lo, T hi) {
    if (!j.is_number()) return config_error(where, "must be a number, got " + j.dump());
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi) ||
        (std::is_integral_v<T> && v != std::floor(v)))
        return config_error(where, "must be " + std::string(std::is_integral_v<T> ? "an integer" : "a number") + " in " +
                                       std::to_string(lo) + ".." + std::to_string(hi) + ", got " + j.dump());
    return static_cast<T>(v);
}

Result<WordOrder> word_order_of(const Json& j, const std::string& where) {
    if (j == "big") return WordOrder::big;
    if (j == "little") return WordOrder::little;
    return config_error(where, "must be \"big\" or \"little\", got " + j.dump());
}

Result<void> only_keys(const Json& obj, const std::string& where, std::initializer_list<const char*> keys) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        bool known = false;
        for (const char* k : keys) known = known || it.key() == k;
        if (known) continue;
        std::string list;
        for (const char* k : keys) list += std::string(list.empty() ? "" : ", ") + k;
        return config_error(where + "/" + it.key(), "unknown key (known: " + list + ")");
    }
    return ok_result();
}

Result<Point> parse_point(const std::string& id, const Json& spec, WordOrder default_order) {
    const std::string where = "points/" + id;
    if (!spec.is_object()) return config_error(where, "must be an object");
    if (auto r = only_keys(spec, where, {"table", "address", "type", "word_order", "scale", "offset", "enum", "text"}); !r.ok())
        return std::move(r).error();
    Point p;
    p.id = id;
    p.word_order = default_order;
    if (!spec.contains("table") || !spec["table"].is_string())
        return config_error(where + "/table", "missing (coil, discrete_input, holding_register or input_register)");
    bool found = false;
    for (const auto& t : table_names)
        if (spec["table"] == t.name) p.table = t.table, found = true;
    if (!found)
        return config_error(where + "/table", "unknown table " + spec["table"].dump() +
                                                  " (coil, discrete_input, holding_register or input_register)");
    if (!spec.contains("address")) return config_error(where + "/address", "missing (0-based protocol address)");
    auto address = number_in<unsigned>(spec["address"], where + "/address", 0, 65535);
    if (!address.ok()) return std::move(address).error();
    p.address = static_cast<std::uint16_t>(address.value());
    p.type = is_bit_table(p.table) ? RegType::boolean : RegType::uint16;
    if (spec.contains("type")) {
        found = false;
        for (const auto& t : type_names)
            if (spec["type"] == t.name) p.type = t.type, found = true;
        if (!found)
            return config_error(where + "/type", "unknown type " + spec["type"].dump() +
                                                     " (bool, int16, uint16, int32, uint32, int64, float32, float64)");
        if (is_bit_table(p.table) && p.type != RegType::boolean)
            return config_error(where + "/type", "a coil or discrete input is a bool");
    }
    if (spec.contains("word_order")) {
        auto order = word_order_of(spec["word_order"], where + "/word_order");
        if (!order.ok()) return std::move(order).error();
        p.word_order = order.value();
    }
    if (spec.contains("scale")) {
        auto scale = number_in<double>(spec["scale"], where + "/scale", -1e300, 1e300);
        if (!scale.ok()) return std::move(scale).error();
        if (scale.value() == 0) return config_error(where + "/scale", "must not be 0");
        p.scale = scale.value();
    }
    if (spec.contains("offset")) {
        auto offset = number_in<double>(spec["offset"], where + "/offset", -1e300, 1e300);
        if (!offset.ok()) return std::move(offset).error();
        p.offset = offset.value();
    }
    if (spec.contains("enum")) {
        const Json& e = spec["enum"];
        if (!e.is_object() || e.empty()) return config_error(where + "/enum", "must be an object {\"<raw value>\": \"<word>\"}");
        if (p.type == RegType::float32 || p.type == RegType::float64)
            return config_error(where + "/enum", "needs an integer type");
        std::set<std::string> words;
        for (auto it = e.begin(); it != e.end(); ++it) {
            char* end = nullptr;
            errno = 0;
            const long long raw = std::strtoll(it.key().c_str(), &end, 10);
            if (it.key().empty() || *end != '\0' || errno != 0)
                return config_error(where + "/enum/" + it.key(), "key must be an integer raw value");
            if (!it.value().is_string()) return config_error(where + "/enum/" + it.key(), "must be a string word");
            if (!words.insert(it.value().get<std::string>()).second)
                return config_error(where + "/enum/" + it.key(), "word " + it.value().dump() + " named twice");
            p.enumeration[raw] = it.value().get<std::string>();
        }
    }
    if (spec.contains("text")) {
        if (!spec["text"].is_boolean()) return config_error(where + "/text", "must be true or false");
        p.as_text = spec["text"].get<bool>();
        if (p.as_text && !p.enumeration.empty()) return config_error(where + "/text", "cannot be combined with enum");
    }
    if (static_cast<unsigned>(p.address) + p.width() > 65536u)
        return config_error(where + "/address", "the value runs past address 65535");
    return p;
}

std::uint64_t combine(const std::uint16_t* words, unsigned n, WordOrder order) {
    std::uint64_t raw = 0;
    for (unsigned i = 0; i < n; ++i) {
        const std::uint16_t w = order == WordOrder::big ? words[i] : words[n - 1 - i];
        raw = (raw << 16) | w;
    }
    return raw;
}

std::vector<std::uint16_t> split(std::uint64_t raw, unsigned n, WordOrder order) {
    std::vector<std::uint16_t> words(n);
    for (unsigned i = 0; i < n; ++i) {
        const auto w = static_cast<std::uint16_t>(raw >> (16 * (n - 1 - i)));
        words[order == WordOrder::big ? i : n - 1 - i] = w;
    }
    return words;
}

bool is_integer_type(RegType t) { return t != RegType::float32 && t != RegType::float64 && t != RegType::boolean; }

/// The integer raw value range of a type.
std::pair<double, double> raw_range(RegType t) {
    switch (t) {
        case RegType::int16: return {-32768.0, 32767.0};
        case RegType::uint16: return {0.0, 65535.0};
        case RegType::int32: return {-2147483648.0, 2147483647.0};
        case RegType::uint32: return {0.0, 4294967295.0};
        // Doubles hold integers exactly up to 2^53: the range a JSON number can mean.
        case RegType::int64: return {-9007199254740992.0, 9007199254740992.0};
        default: return {0.0, 1.0};
    }
}

/// The RTU keys: `device` selects a serial line instead of host:port.
Result<void> parse_serial(const Json& json, Config& c) {
    constexpr const char* serial_keys[] = {"baud", "parity", "data_bits", "stop_bits", "byte_timeout_ms", "frame_gap_us"};
    if (!json.contains("device")) {
        for (const char* key : serial_keys)
            if (json.contains(key)) return config_error(key, "only for Modbus RTU: name the serial line with \"device\"");
        return ok_result();
    }
    for (const char* key : {"host", "port"})
        if (json.contains(key)) return config_error(key, "a map with \"device\" (Modbus RTU) has no host or port (Modbus TCP)");
    if (!json["device"].is_string() || json["device"].get<std::string>().empty())
        return config_error("device", "must be the serial device's path, e.g. \"/dev/ttyUSB0\"");
    SerialLine line;
    line.device = json["device"].get<std::string>();
    if (json.contains("baud")) {
        auto v = number_in<int>(json["baud"], "baud", 50, 4000000);
        if (!v.ok()) return std::move(v).error();
        line.baud = v.value();
    }
    if (json.contains("parity")) {
        const Json& p = json["parity"];
        if (p == "N" || p == "none") line.parity = 'N';
        else if (p == "E" || p == "even") line.parity = 'E';
        else if (p == "O" || p == "odd") line.parity = 'O';
        else return config_error("parity", "must be \"N\", \"E\" or \"O\" (none, even, odd), got " + p.dump());
    }
    if (json.contains("data_bits")) {
        auto v = number_in<int>(json["data_bits"], "data_bits", 5, 8);
        if (!v.ok()) return std::move(v).error();
        line.data_bits = v.value();
    }
    if (json.contains("stop_bits")) {
        auto v = number_in<int>(json["stop_bits"], "stop_bits", 1, 2);
        if (!v.ok()) return std::move(v).error();
        line.stop_bits = v.value();
    }
    if (json.contains("frame_gap_us")) {
        auto v = number_in<int>(json["frame_gap_us"], "frame_gap_us", 0, 1000000);
        if (!v.ok()) return std::move(v).error();
        line.frame_gap = std::chrono::microseconds(v.value());
        if (v.value() != 0 && line.frame_gap < line.minimum_frame_gap())
            return config_error("frame_gap_us", "below 3.5 character times at " + std::to_string(line.baud) + " baud (" +
                                                    std::to_string(line.minimum_frame_gap().count()) +
                                                    " us, Modbus over Serial Line 2.5.1.1)");
    }
    if (json.contains("byte_timeout_ms")) {
        auto v = number_in<int>(json["byte_timeout_ms"], "byte_timeout_ms", 1, 10000);
        if (!v.ok()) return std::move(v).error();
        c.byte_timeout = std::chrono::milliseconds(v.value());
    }
    c.serial = std::move(line);
    return ok_result();
}

}  // namespace

unsigned Point::width() const {
    switch (type) {
        case RegType::int32:
        case RegType::uint32:
        case RegType::float32: return 2;
        case RegType::int64:
        case RegType::float64: return 4;
        default: return 1;
    }
}

std::chrono::microseconds SerialLine::minimum_frame_gap() const {
    // Modbus over Serial Line 2.5.1.1: a frame ends after 3.5 character times
    // of silence; above 19200 baud a fixed 1.75 ms. A character is a start
    // bit, the data bits, the parity bit if any and the stop bits.
    if (baud > 19200) return std::chrono::microseconds(1750);
    const int bits = 1 + data_bits + (parity == 'N' ? 0 : 1) + stop_bits;
    return std::chrono::microseconds(static_cast<long long>(std::ceil(3.5 * bits * 1e6 / baud)));
}

std::string SerialLine::describe() const {
    return device + " " + std::to_string(baud) + " " + std::to_string(data_bits) + parity + std::to_string(stop_bits);
}

bool SerialLine::same_settings(const SerialLine& o) const {
    return baud == o.baud && parity == o.parity && data_bits == o.data_bits && stop_bits == o.stop_bits && frame_gap == o.frame_gap;
}

std::string Config::endpoint() const {
    if (serial) return "rtu " + serial->device + " slave " + std::to_string(unit_id);
    return host + ":" + std::to_string(port);
}

const Point* Config::find(const std::string& id) const {
    auto it = by_id.find(id);
    return it == by_id.end() ? nullptr : &points[it->second];
}

Result<Config> parse_config(const Json& json) {
    if (!json.is_object()) return config_error("/", "must be an object with \"host\" and \"points\"");
    if (auto r = only_keys(json, "",
                           {"host", "port", "unit_id", "slave_id", "timeout_ms", "backoff_ms", "word_order", "max_gap", "points",
                            "device", "baud", "parity", "data_bits", "stop_bits", "byte_timeout_ms", "frame_gap_us"});
        !r.ok())
        return std::move(r).error();
    Config c;
    if (auto r = parse_serial(json, c); !r.ok()) return std::move(r).error();
    if (json.contains("host")) {
        if (!json["host"].is_string() || json["host"].get<std::string>().empty())
            return config_error("host", "must be a host name or address");
        c.host = json["host"].get<std::string>();
    }
    if (json.contains("port")) {
        auto v = number_in<int>(json["port"], "port", 1, 65535);
        if (!v.ok()) return std::move(v).error();
        c.port = v.value();
    }
    if (json.contains("unit_id") && json.contains("slave_id"))
        return config_error("slave_id", "names the same as unit_id: give one of them");
    for (const char* key : {"unit_id", "slave_id"}) {
        if (!json.contains(key)) continue;
        // Modbus over Serial Line 2.2: slave addresses are 1..247 (0 is a
        // broadcast, which no slave answers; 248..255 are reserved).
        auto v = c.serial ? number_in<int>(json[key], key, 1, 247) : number_in<int>(json[key], key, 0, 255);
        if (!v.ok()) return std::move(v).error();
        c.unit_id = v.value();
    }
    if (json.contains("timeout_ms")) {
        auto v = number_in<int>(json["timeout_ms"], "timeout_ms", 1, 60000);
        if (!v.ok()) return std::move(v).error();
        c.timeout = std::chrono::milliseconds(v.value());
    }
    if (json.contains("backoff_ms")) {
        const Json& b = json["backoff_ms"];
        if (!b.is_object()) return config_error("backoff_ms", "must be {\"min\": ms, \"max\": ms}");
        if (auto r = only_keys(b, "backoff_ms", {"min", "max"}); !r.ok()) return std::move(r).error();
        if (b.contains("min")) {
            auto v = number_in<int>(b["min"], "backoff_ms/min", 1, 3600000);
            if (!v.ok()) return std::move(v).error();
            c.backoff_min = std::chrono::milliseconds(v.value());
        }
        if (b.contains("max")) {
            auto v = number_in<int>(b["max"], "backoff_ms/max", 1, 3600000);
            if (!v.ok()) return std::move(v).error();
            c.backoff_max = std::chrono::milliseconds(v.value());
        }
        if (c.backoff_max < c.backoff_min) return config_error("backoff_ms", "max is smaller than min");
    }
    WordOrder order = WordOrder::big;
    if (json.contains("word_order")) {
        auto v = word_order_of(json["word_order"], "word_order");
        if (!v.ok()) return std::move(v).error();
        order = v.value();
    }
    if (json.contains("max_gap")) {
        auto v = number_in<unsigned>(json["max_gap"], "max_gap", 0, 120);
        if (!v.ok()) return std::move(v).error();
        c.max_gap = v.value();
    }
    if (!json.contains("points") || !json["points"].is_object() || json["points"].empty())
        return config_error("points", "missing: an object {\"<data item id>\": {\"table\", \"address\", ...}}");
    for (auto it = json["points"].begin(); it != json["points"].end(); ++it) {
        auto p = parse_point(it.key(), it.value(), order);
        if (!p.ok()) return std::move(p).error();
        c.by_id[it.key()] = c.points.size();
        c.points.push_back(std::move(p).value());
    }
    return c;
}

std::vector<ReadSpan> plan_reads(const std::vector<const Point*>& points, unsigned max_gap) {
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < points.size(); ++i)
        if (points[i]) order.push_back(i);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (points[a]->table != points[b]->table) return points[a]->table < points[b]->table;
        return points[a]->address < points[b]->address;
    });
    std::vector<ReadSpan> spans;
    for (std::size_t i : order) {
        const Point& p = *points[i];
        // Modbus application protocol: at most 125 registers (0x03/0x04) or
        // 2000 bits (0x01/0x02) per read request.
        const unsigned limit = is_bit_table(p.table) ? 2000u : 125u;
        const unsigned end = static_cast<unsigned>(p.address) + p.width();
        if (!spans.empty()) {
            ReadSpan& s = spans.back();
            const unsigned s_end = static_cast<unsigned>(s.start) + s.count;
            if (s.table == p.table && p.address <= s_end + max_gap && std::max(end, s_end) - s.start <= limit) {
                s.count = static_cast<std::uint16_t>(std::max(end, s_end) - s.start);
                s.members.push_back(i);
                continue;
            }
        }
        spans.push_back(ReadSpan{p.table, p.address, static_cast<std::uint16_t>(p.width()), {i}});
    }
    return spans;
}

Result<Json> decode(const Point& p, const std::uint16_t* words) {
    const std::uint64_t raw = combine(words, p.width(), p.word_order);
    double value = 0;
    std::int64_t integer = 0;
    switch (p.type) {
        case RegType::boolean: return Json(raw != 0);
        case RegType::int16: integer = static_cast<std::int16_t>(raw); break;
        case RegType::uint16: integer = static_cast<std::uint16_t>(raw); break;
        case RegType::int32: integer = static_cast<std::int32_t>(raw); break;
        case RegType::uint32: integer = static_cast<std::uint32_t>(raw); break;
        case RegType::int64: integer = static_cast<std::int64_t>(raw); break;
        case RegType::float32: {
            const auto bits = static_cast<std::uint32_t>(raw);
            float f;
            std::memcpy(&f, &bits, sizeof f);
            value = f;
            break;
        }
        case RegType::float64: std::memcpy(&value, &raw, sizeof value); break;
    }
    if (is_integer_type(p.type)) {
        if (!p.enumeration.empty()) {
            auto it = p.enumeration.find(integer);
            if (it == p.enumeration.end())
                return make_error(ErrorCode::unavailable,
                                  "modbus " + p.id + ": raw value " + std::to_string(integer) + " is not in the map's enum");
            return Json(it->second);
        }
        if (p.scale == 1.0 && p.offset == 0.0) return p.as_text ? Json(std::to_string(integer)) : Json(integer);
        value = static_cast<double>(integer);
    }
    if (!std::isfinite(value)) return Json(nullptr);  // NaN/Inf are not JSON: the slot is null
    const Json number(value * p.scale + p.offset);
    return p.as_text ? Json(number.dump()) : number;
}

Json decode_bit(const Point& p, bool bit) {
    if (!p.enumeration.empty()) {
        auto it = p.enumeration.find(bit ? 1 : 0);
        if (it != p.enumeration.end()) return Json(it->second);
    }
    return Json(bit);
}

Result<Encoded> encode(const Point& p, const Json& value) {
    Encoded out;
    std::optional<double> number;
    if (!p.enumeration.empty() && value.is_string()) {
        for (const auto& [raw, word] : p.enumeration)
            if (word == value.get<std::string>()) number = static_cast<double>(raw);
        if (!number)
            return make_error(ErrorCode::out_of_range,
                              "modbus " + p.id + ": " + value.dump() + " is not one of the map's enum words");
    } else if (value.is_boolean()) {
        number = value.get<bool>() ? 1.0 : 0.0;
    } else if (value.is_number()) {
        number = value.get<double>();
    } else if (p.as_text && value.is_string()) {
        char* end = nullptr;
        const std::string& text = value.get_ref<const std::string&>();
        const double parsed = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0')
            return make_error(ErrorCode::value_type, "modbus " + p.id + ": " + value.dump() + " is not a number");
        number = parsed;
    } else {
        return make_error(ErrorCode::value_type, "modbus " + p.id + ": cannot write " + value.dump() + " (a number or bool)");
    }
    if (p.table == Table::coil) {
        if (*number != 0.0 && *number != 1.0)
            return make_error(ErrorCode::out_of_range, "modbus " + p.id + ": a coil is 0/1 or false/true");
        out.bit = *number == 1.0;
        return out;
    }
    if (p.type == RegType::boolean) {
        out.words = {static_cast<std::uint16_t>(*number != 0.0)};
        return out;
    }
    // The enumeration's raw values are already raw; numbers are scaled.
    const bool from_enum = !p.enumeration.empty() && value.is_string();
    const double raw = from_enum ? *number : (*number - p.offset) / p.scale;
    if (!std::isfinite(raw)) return make_error(ErrorCode::out_of_range, "modbus " + p.id + ": value not finite");
    std::uint64_t bits = 0;
    if (p.type == RegType::float32) {
        if (std::fabs(raw) > std::numeric_limits<float>::max())
            return make_error(ErrorCode::out_of_range, "modbus " + p.id + ": out of float32 range");
        const float f = static_cast<float>(raw);
        std::uint32_t b;
        std::memcpy(&b, &f, sizeof b);
        bits = b;
    } else if (p.type == RegType::float64) {
        std::memcpy(&bits, &raw, sizeof bits);
    } else {
        const double rounded = std::nearbyint(raw);
        const auto [lo, hi] = raw_range(p.type);
        if (rounded < lo || rounded > hi)
            return make_error(ErrorCode::out_of_range, "modbus " + p.id + ": " + value.dump() + " is raw " +
                                                           std::to_string(rounded) + ", outside the register's range");
        bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(rounded));
    }
    out.words = split(bits, p.width(), p.word_order);
    return out;
}

}  // namespace nclink::modbus
