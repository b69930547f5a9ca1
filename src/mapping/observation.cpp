// mtconnect_observations: an NC-Link JSON value as the text of a Streams
// observation (MTConnectStreams_1.4.xsd value patterns and enumerations).
#include "mapping/plan.hpp"

#include <nclink/mapping.hpp>

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace nclink {
namespace {

constexpr std::string_view kUnavailable = "UNAVAILABLE";

std::string trim(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
    return std::string(text);
}

/// A finite number from a JSON number or numeric string.
std::optional<double> number_of(const Json& value) {
    if (value.is_number()) {
        const double d = value.get<double>();
        if (std::isfinite(d)) return d;
        return std::nullopt;
    }
    if (value.is_string()) {
        const std::string text = trim(value.get_ref<const std::string&>());
        if (text.empty()) return std::nullopt;
        char* end = nullptr;
        const double d = std::strtod(text.c_str(), &end);
        if (end == text.c_str() + text.size() && std::isfinite(d)) return d;
    }
    return std::nullopt;
}

/// An integer from a JSON integer, an integral number or an integer string.
std::optional<long long> integer_of(const Json& value) {
    if (value.is_number_integer()) return value.get<long long>();
    if (value.is_number_float()) {
        const double d = value.get<double>();
        if (std::isfinite(d) && std::floor(d) == d && std::fabs(d) < 9e18) return static_cast<long long>(d);
        return std::nullopt;
    }
    if (value.is_string()) {
        const std::string text = trim(value.get_ref<const std::string&>());
        if (text.empty()) return std::nullopt;
        std::size_t i = (text[0] == '+' || text[0] == '-') ? 1 : 0;
        if (i == text.size()) return std::nullopt;
        for (std::size_t k = i; k < text.size(); ++k)
            if (!std::isdigit(static_cast<unsigned char>(text[k]))) return std::nullopt;
        if (text.size() > 19) return std::nullopt;
        return std::strtoll(text.c_str(), nullptr, 10);
    }
    return std::nullopt;
}

MtObservation unavailable(const MtDataItem& item, bool exact) {
    return MtObservation{item.element, std::string(kUnavailable), {}, exact};
}

/// One alarm of a WARNING value (table 14: number, text, emerge_time, key_value).
MtObservation fault(const Json& alarm) {
    MtObservation o{"Fault", {}, {}, true};
    if (alarm.is_object()) {
        if (const auto it = alarm.find("number"); it != alarm.end())
            o.native_code = it->is_string() ? it->get<std::string>() : mapping_detail::scalar_text(*it);
        if (const auto it = alarm.find("text"); it != alarm.end())
            o.value = it->is_string() ? it->get<std::string>() : it->dump(-1, ' ', false, Json::error_handler_t::replace);
    } else if (alarm.is_string()) {
        o.value = alarm.get<std::string>();
    } else if (alarm.is_number()) {
        o.native_code = mapping_detail::scalar_text(alarm);
    }
    return o;
}

/// No active alarm: null-like or empty values.
bool no_alarm(const Json& value) {
    return (value.is_object() && value.empty()) || (value.is_array() && value.empty()) ||
           (value.is_boolean() && !value.get<bool>()) || (value.is_string() && value.get_ref<const std::string&>().empty()) ||
           (value.is_number() && value.get<double>() == 0);
}

std::vector<MtObservation> condition(const Json& value) {
    if (value.is_null()) return {MtObservation{"Unavailable", {}, {}, true}};
    if (no_alarm(value)) return {MtObservation{"Normal", {}, {}, true}};
    std::vector<MtObservation> out;
    if (value.is_array()) {
        for (const auto& alarm : value)
            if (!alarm.is_null() && !no_alarm(alarm)) out.push_back(fault(alarm));
        if (out.empty()) out.push_back(MtObservation{"Normal", {}, {}, true});
        return out;
    }
    out.push_back(fault(value));
    return out;
}

}  // namespace

std::vector<MtObservation> mtconnect_observations(const MtDataItem& item, const Json& value) {
    if (item.target != MtTarget::data_item && item.target != MtTarget::fallback) return {};
    if (item.value_form == MtValueForm::condition) return condition(value);
    if (value.is_null()) return {unavailable(item, true)};
    switch (item.value_form) {
        case MtValueForm::number: {
            if (value.is_array() && item.units == "MILLIMETER_3D") {
                std::string text;
                for (const auto& v : value) {
                    const auto d = number_of(v);
                    if (!d) return {unavailable(item, false)};
                    if (!text.empty()) text += ' ';
                    text += mapping_detail::number_text(*d * item.scale + item.offset);
                }
                return {MtObservation{item.element, text, {}, true}};
            }
            const auto d = number_of(value);
            if (!d) return {unavailable(item, false)};
            const double converted = *d * item.scale + item.offset;
            if (!std::isfinite(converted)) return {unavailable(item, false)};
            return {MtObservation{item.element, mapping_detail::number_text(converted), {}, true}};
        }
        case MtValueForm::integer: {
            const auto n = integer_of(value);
            if (!n) return {unavailable(item, false)};
            return {MtObservation{item.element, std::to_string(*n), {}, true}};
        }
        case MtValueForm::enumerated: {
            const std::string key =
                value.is_string() ? trim(value.get_ref<const std::string&>()) : mapping_detail::scalar_text(value);
            for (const auto& [nclink, mtconnect] : item.values)
                if (nclink == key) return {MtObservation{item.element, mtconnect, {}, true}};
            return {unavailable(item, false)};
        }
        case MtValueForm::text:
        case MtValueForm::condition: break;
    }
    if (value.is_string()) return {MtObservation{item.element, value.get<std::string>(), {}, true}};
    if (value.is_number() || value.is_boolean())
        return {MtObservation{item.element, mapping_detail::scalar_text(value), {}, true}};
    return {MtObservation{item.element, value.dump(-1, ' ', false, Json::error_handler_t::replace), {}, true}};
}

}  // namespace nclink
