#include "mtconnect/observation_values.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace nclink::mtconnect {

namespace {

bool is_unavailable(std::string_view text) {
    if (text.size() != 11) return false;
    for (std::size_t i = 0; i < text.size(); ++i)
        if (std::toupper(static_cast<unsigned char>(text[i])) != "UNAVAILABLE"[i]) return false;
    return true;
}

std::string trimmed(std::string_view text) {
    std::size_t b = 0, e = text.size();
    while (b < e && std::isspace(static_cast<unsigned char>(text[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(text[e - 1]))) --e;
    return std::string(text.substr(b, e - b));
}

bool parse_double(const std::string& text, double& out) {
    if (text.empty()) return false;
    errno = 0;
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return errno == 0 && end && *end == '\0' && std::isfinite(out);
}

Json number(const ItemBinding& item, const std::string& text) {
    double d = 0;
    if (!parse_double(text, d)) return nullptr;
    return (d - item.offset) / item.scale;
}

Json integer_or_text(const std::string& text) {
    if (text.empty() || text.size() > 18) return text;
    const std::size_t start = text[0] == '-' || text[0] == '+' ? 1 : 0;
    if (start == text.size() || text.find_first_not_of("0123456789", start) != std::string::npos) return text;
    return std::stoll(text);
}

}  // namespace

Json value_of(const ItemBinding& item, std::string_view raw) {
    const std::string text = item.rule == ValueRule::text || item.rule == ValueRule::json ? std::string(raw) : trimmed(raw);
    if (item.rule == ValueRule::words || item.rule == ValueRule::boolean)
        for (const auto& [mt, word] : item.words)
            if (mt == text) {
                if (item.rule == ValueRule::boolean && (word == "true" || word == "false")) return word == "true";
                return word;
            }
    if (is_unavailable(trimmed(raw))) return nullptr;
    switch (item.rule) {
        case ValueRule::number: return number(item, text);
        case ValueRule::number_3d: {
            std::istringstream in(text);
            Json out = Json::array();
            std::string part;
            while (in >> part) {
                Json v = number(item, part);
                if (v.is_null()) return nullptr;
                out.push_back(v);
            }
            return out.empty() ? Json(nullptr) : out;
        }
        case ValueRule::integer: {
            Json v = integer_or_text(text);
            return v.is_string() ? Json(nullptr) : v;
        }
        case ValueRule::boolean:
            if (text == "true" || text == "TRUE") return true;
            if (text == "false" || text == "FALSE") return false;
            return text;  // a word outside the table: kept, the reader sees what came
        case ValueRule::words: return text;
        case ValueRule::json: {
            // nclink writes objects and lists as compact JSON text (docs/mapping.md).
            if (!text.empty() && (text.front() == '{' || text.front() == '[')) {
                Json parsed = Json::parse(text, nullptr, false);
                if (!parsed.is_discarded()) return parsed;
            }
            double d = 0;
            if (parse_double(text, d)) return integer_or_text(text).is_number() ? integer_or_text(text) : Json(d);
            return text;
        }
        default: return std::string(raw);
    }
}

void ConditionAlarms::apply(std::string_view level, const std::string& native_code, const std::string& text) {
    if (level == "Unavailable") {
        available_ = false;
        active_.clear();
        return;
    }
    available_ = true;
    if (level == "Normal") {
        if (native_code.empty()) active_.clear();
        else active_.erase(native_code);
        return;
    }
    active_[native_code] = Alarm{level == "Fault" ? "FAULT" : "WARNING", text};
}

void ConditionAlarms::reset() {
    available_ = false;
    active_.clear();
}

Json ConditionAlarms::value() const {
    if (!available_) return nullptr;
    Json out = Json::array();
    for (const auto& [code, alarm] : active_) {
        Json a = {{"number", integer_or_text(code)}, {"text", alarm.text}, {"level", alarm.level}};
        if (code.empty()) a.erase("number");
        out.push_back(std::move(a));
    }
    return out;
}

}  // namespace nclink::mtconnect
