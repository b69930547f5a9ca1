// What a Set does to the simulated machine: alarms written by the
// application, the mill's roles (override, pinned positions, program) and
// the generic stored/pinned values.
#include "sim_driver_impl.hpp"

#include <nclink/values.hpp>

#include <algorithm>
#include <cmath>

namespace nclink {

using sim::MillMethod;
using sim::MillRole;
using sim_detail::as_count;

Result<void> SimDriver::Impl::commit_alarms(const Item& item, const Json& value) {
    std::vector<Json> next;
    auto take = [&](const Json& a) -> Result<void> {
        if (a.is_null() || (a.is_object() && a.empty())) return ok_result();
        if (!a.is_object()) return make_error(ErrorCode::value_type, "a WARNING is an object {number, text, emerge_time}");
        Json w = a;
        if (!w.contains("number")) w["number"] = "0";
        if (!w.contains("text")) w["text"] = "";
        if (!w.contains("emerge_time")) w["emerge_time"] = wall_ms;
        next.push_back(std::move(w));
        return ok_result();
    };
    if (item.object->kind == DataKind::single) {
        auto r = take(value);
        if (!r.ok()) return r;
    } else {
        for (const auto& a : value) {
            auto r = take(a);
            if (!r.ok()) return r;
        }
    }
    const bool raised = next.size() > alarms.size();
    alarms = std::move(next);
    suppress_spontaneous();
    if (raised && mill) mill->feed_hold();
    return ok_result();
}

Result<void> SimDriver::Impl::commit_mill(Item& item, MillRole role, Json value) {
    switch (role) {
        case MillRole::feed_override:
            if (!value.is_number()) return make_error(ErrorCode::value_type, "feed override is a number (percent)");
            return mill->set_feed_override(value.get<double>());
        case MillRole::spindle_override:
            if (!value.is_number()) return make_error(ErrorCode::value_type, "spindle override is a number (percent)");
            return mill->set_spindle_override(value.get<double>());
        case MillRole::status: {
            const std::string s = value.is_string() ? value.get<std::string>() : std::string();
            if (s == "running") {
                if (emergency) return make_error(ErrorCode::permission_denied, "emergency stop is active");
                return mill->cycle_start();
            }
            if (s == "holding") {
                mill->feed_hold();
                return ok_result();
            }
            if (s == "free") {
                mill->reset();
                return ok_result();
            }
            return make_error(ErrorCode::out_of_range, "status must be running, free or holding");
        }
        case MillRole::work_mode: {
            const std::string s = value.is_string() ? value.get<std::string>() : std::string();
            if (s != "manual" && s != "auto") return make_error(ErrorCode::out_of_range, "work mode must be manual or auto");
            mill->set_manual(s == "manual");
            return ok_result();
        }
        case MillRole::part_count: {
            auto n = as_count(value);
            if (!n) return make_error(ErrorCode::value_type, "part count is a non-negative integer string");
            mill->set_part_count(*n);
            return ok_result();
        }
        case MillRole::program:
            if (!value.is_string()) return make_error(ErrorCode::value_type, "program name is a string");
            mill->set_program_name(value.get<std::string>());
            return ok_result();
        case MillRole::emergency_stop:
            if (!value.is_boolean()) return make_error(ErrorCode::value_type, "emergency stop is a boolean");
            emergency = value.get<bool>();
            if (emergency) {
                mill->reset();
                add_alarm("9000", "emergency stop");
            }
            return ok_result();
        case MillRole::warning: return commit_alarms(item, value);
        default:
            // Computed outputs (positions, loads, ...): held at the written
            // value until the reset method.
            item.pinned = std::move(value);
            return ok_result();
    }
}

Result<void> SimDriver::Impl::commit(Item& item, Json value) {
    if (item.use_stored) {
        item.generated = false;
        item.stored = std::move(value);
        return ok_result();
    }
    if (item.role) return commit_mill(item, *item.role, std::move(value));
    if (item.alarm) return commit_alarms(item, value);
    if (item.generator.shape == sim::Shape::counter) {
        auto n = as_count(value);
        if (!n) return make_error(ErrorCode::value_type, "a counter is a non-negative integer string");
        item.generator.base = static_cast<double>(*n);
        item.generator.origin = t;
        return ok_result();
    }
    if (item.generator.shape == sim::Shape::ramp && value.is_number()) {
        item.generator.base = value.get<double>();
        item.generator.origin = t;
        return ok_result();
    }
    item.pinned = std::move(value);
    return ok_result();
}

// ------------------------------------------------------------------ API --

}  // namespace nclink
