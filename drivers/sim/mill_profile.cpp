#include "mill_profile.hpp"

#include "sim_random.hpp"

#include <array>
#include <cmath>
#include <string_view>
#include <utility>

namespace nclink::sim {

namespace {

constexpr std::string_view mill_guid = "nclink-sim-mill-01";

constexpr std::array<std::pair<std::string_view, MillRole>, 27> item_ids{{
    {"x_position", MillRole::x_position},
    {"y_position", MillRole::y_position},
    {"z_position", MillRole::z_position},
    {"x_speed", MillRole::x_speed},
    {"y_speed", MillRole::y_speed},
    {"z_speed", MillRole::z_speed},
    {"x_load", MillRole::x_load},
    {"y_load", MillRole::y_load},
    {"z_load", MillRole::z_load},
    {"x_current", MillRole::x_current},
    {"y_current", MillRole::y_current},
    {"z_current", MillRole::z_current},
    {"spindle_speed", MillRole::spindle_speed},
    {"spindle_load", MillRole::spindle_load},
    {"spindle_override", MillRole::spindle_override},
    {"spindle_mode", MillRole::spindle_mode},
    {"status", MillRole::status},
    {"work_mode", MillRole::work_mode},
    {"program", MillRole::program},
    {"line_number", MillRole::line_number},
    {"part_count", MillRole::part_count},
    {"feed_speed", MillRole::feed_speed},
    {"feed_override", MillRole::feed_override},
    {"tool_number", MillRole::tool_number},
    {"warning", MillRole::warning},
    {"emergency_stop", MillRole::emergency_stop},
    {"door_closed", MillRole::door_closed},
}};

constexpr std::array<std::pair<std::string_view, MillMethod>, 4> method_ids{{
    {"cycle_start", MillMethod::cycle_start},
    {"feed_hold", MillMethod::feed_hold},
    {"reset", MillMethod::reset},
    {"program_transfer", MillMethod::program_transfer},
}};

constexpr std::array<std::string_view, 5> signature_ids{"x_position", "y_position", "z_position", "spindle_speed", "status"};

SampleValue round_to(double v, int decimals) {
    const double scale = std::pow(10.0, decimals);
    return SampleValue::float64(std::round(v * scale) / scale);
}

/// An integral percent as an integer, a fractional one as it was set.
SampleValue percent(double v) {
    if (v == std::floor(v)) return SampleValue::int64(static_cast<std::int64_t>(v));
    return SampleValue::float64(v);
}

SampleValue text_of(std::string& text, std::string_view value) {
    text.assign(value.data(), value.size());
    return SampleValue::text(text);
}

/// Noise in [-1, 1] for measurement jitter.
double jitter(std::uint64_t stream, MillRole role, double t) {
    return 2.0 * drift(hash_pair(stream, static_cast<std::uint64_t>(role)), t, 0.7) - 1.0;
}

}  // namespace

std::optional<MillProfile> recognise_mill(const Model& model, const Device& device) {
    bool is_mill = device.guid && *device.guid == mill_guid;
    if (!is_mill) {
        is_mill = true;
        for (auto id : signature_ids) {
            const Device* owner = model.owning_device(id);
            if (!model.data_object(id) || !owner || owner->id != device.id) is_mill = false;
        }
    }
    if (!is_mill) return std::nullopt;
    MillProfile profile;
    for (const auto& [id, role] : item_ids) {
        const Device* owner = model.owning_device(id);
        if (model.data_object(id) && owner && owner->id == device.id) profile.items.emplace(std::string(id), role);
    }
    for (const auto& [id, method] : method_ids)
        if (model.method(id)) profile.methods.emplace(std::string(id), method);
    // The spindle limit the model declares, when it does.
    if (const DataObject* limit = model.data_object("spindle_max_speed"); limit && limit->value && limit->value->is_number())
        profile.config.spindle_max_rpm = limit->value->get<double>();
    return profile;
}

SampleValue mill_sample(MillRole role, const MillMachine& m, double t, std::uint64_t stream, std::string& text) {
    const Vec3 v = m.velocity();
    const double rapid = m.config().rapid_mm_min;
    auto axis_load = [&](int axis) {
        // Percent: friction share of the speed, plus cutting force while in material.
        const double load = 4.0 + 20.0 * std::abs(v[axis]) / rapid + (m.cutting() ? 18.0 : 0.0) + 1.5 * jitter(stream, role, t);
        return std::max(0.0, load);
    };
    auto axis_current = [&](int axis) { return std::max(0.0, 0.4 + 0.12 * axis_load(axis) + 0.05 * jitter(stream, role, t)); };
    switch (role) {
        case MillRole::x_position: return round_to(m.position()[0], 3);
        case MillRole::y_position: return round_to(m.position()[1], 3);
        case MillRole::z_position: return round_to(m.position()[2], 3);
        case MillRole::x_speed: return round_to(v[0], 1);
        case MillRole::y_speed: return round_to(v[1], 1);
        case MillRole::z_speed: return round_to(v[2], 1);
        case MillRole::x_load: return round_to(axis_load(0), 1);
        case MillRole::y_load: return round_to(axis_load(1), 1);
        case MillRole::z_load: return round_to(axis_load(2), 1);
        case MillRole::x_current: return round_to(axis_current(0), 2);
        case MillRole::y_current: return round_to(axis_current(1), 2);
        case MillRole::z_current: return round_to(axis_current(2), 2);
        case MillRole::spindle_speed: return SampleValue::int64(static_cast<std::int64_t>(std::llround(m.spindle_speed())));
        case MillRole::spindle_load: {
            if (m.spindle_speed() <= 0) return SampleValue::float64(0.0);
            const double load = 8.0 + 25.0 * m.spindle_speed() / m.config().spindle_max_rpm + (m.cutting() ? 30.0 : 0.0) +
                                2.0 * jitter(stream, role, t);
            return round_to(std::max(0.0, load), 1);
        }
        case MillRole::spindle_override: return percent(m.spindle_override());
        case MillRole::spindle_mode:
            return text_of(text, m.spindle_direction() > 0 ? "forward" : m.spindle_direction() < 0 ? "reverse" : "stop");
        case MillRole::status: return text_of(text, to_string(m.status()));
        case MillRole::work_mode: return text_of(text, m.manual() ? "manual" : "auto");
        case MillRole::program: return text_of(text, m.program_name());
        // Short decimal texts: within std::string's own buffer, no heap.
        case MillRole::line_number: return text_of(text, m.line_number());
        case MillRole::part_count: return text_of(text, std::to_string(m.part_count()));
        case MillRole::feed_speed: return round_to(m.path_speed() / 60.0, 2);  // model units: mm/s
        case MillRole::feed_override: return percent(m.feed_override());
        case MillRole::tool_number: return SampleValue::int64(m.tool_number());
        case MillRole::door_closed: return SampleValue::boolean(m.status() != RunStatus::free);  // opened between cycles only
        case MillRole::warning:
        case MillRole::emergency_stop: break;  // held by the driver (alarms, E-stop)
    }
    return SampleValue::null();
}

Json mill_reading(MillRole role, const MillMachine& m, double t, std::uint64_t stream) {
    std::string text;
    const SampleValue v = mill_sample(role, m, t, stream, text);
    switch (v.kind()) {
        case SampleValue::Kind::boolean: return v.as_bool();
        case SampleValue::Kind::int64: return v.as_int64();
        case SampleValue::Kind::uint64: return v.as_uint64();
        case SampleValue::Kind::float64: return v.as_double();
        case SampleValue::Kind::text: return std::string(v.as_text());
        default: return nullptr;
    }
}

}  // namespace nclink::sim
