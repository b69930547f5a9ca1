// The one place that knows sim-mill.json: which data objects and methods of
// the model the mill simulation drives, and how each reads from the machine
// state. Every other id of the model falls back to the generic simulation.
#pragma once

#include "mill_kinematics.hpp"

#include <nclink/json.hpp>
#include <nclink/model.hpp>
#include <nclink/sample_value.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>

namespace nclink::sim {

enum class MillRole {
    x_position,
    y_position,
    z_position,
    x_speed,
    y_speed,
    z_speed,
    x_load,
    y_load,
    z_load,
    x_current,
    y_current,
    z_current,
    spindle_speed,
    spindle_load,
    spindle_override,
    spindle_mode,
    status,
    work_mode,
    program,
    line_number,
    part_count,
    feed_speed,
    feed_override,
    tool_number,
    warning,
    emergency_stop,
    door_closed,
};

enum class MillMethod { cycle_start, feed_hold, reset, program_transfer };

struct MillProfile {
    std::unordered_map<std::string, MillRole> items;
    std::unordered_map<std::string, MillMethod> methods;
    MillConfig config;
};

/// The mill profile when `device` is the simulated mill: its guid is
/// "nclink-sim-mill-01", or it has the mill's well-known ids (positions,
/// spindle speed, status). Only ids present in the model are mapped.
std::optional<MillProfile> recognise_mill(const Model& model, const Device& device);

/// The value of a mill item now; `t` (seconds) and `stream` drive the
/// measurement noise of loads and currents.
Json mill_reading(MillRole role, const MillMachine& machine, double t, std::uint64_t stream);
/// The same value as a sample, for the sampling path: a text is written
/// into `text` (kept by the caller, so once it has room no reading
/// allocates) and the sample views it. Null for the roles the driver holds.
SampleValue mill_sample(MillRole role, const MillMachine& machine, double t, std::uint64_t stream, std::string& text);

}  // namespace nclink::sim
