// The simulated mill's machine state: a program executing block by block,
// the tool moving along the interpolated path at feed x feed override,
// the spindle ramping towards S x spindle override, and run status.
// Integration is exact per block (constant speed between events), so the
// state at a time does not depend on how often advance() is called beyond
// floating-point rounding.
#pragma once

#include "gcode_program.hpp"

#include <nclink/result.hpp>

#include <array>
#include <cstdint>
#include <string>

namespace nclink::sim {

using Vec3 = std::array<double, 3>;

struct MillConfig {
    double rapid_mm_min = 6000;         ///< G0 speed at 100 %
    double spindle_max_rpm = 12000;     ///< upper limit of the actual speed
    double spindle_accel_rpm_s = 4000;  ///< ramp of the actual spindle speed
    double tool_change_s = 2;           ///< time an M6 takes
    double max_override = 150;          ///< percent, feed and spindle
};

enum class RunStatus { running, free, holding };

/// "running", "free", "holding" (table 15).
const char* to_string(RunStatus status) noexcept;

class MillMachine {
public:
    MillMachine(Program program, MillConfig config, bool autostart);

    /// Runs the machine for `dt` seconds.
    void advance(double dt);

    // Operator actions.
    /// Starts (free) or resumes (holding) the program. Refused in manual mode.
    Result<void> cycle_start();
    void feed_hold();
    /// Stops the program, rewinds to its first block (line 0), stops the spindle.
    void reset();
    /// Percent; out of [0, max_override] is Out of Range (101).
    Result<void> set_feed_override(double percent);
    Result<void> set_spindle_override(double percent);
    /// Manual mode stops a running program (status free).
    void set_manual(bool manual);
    void set_part_count(std::int64_t count) { part_count_ = count; }
    void set_program_name(std::string name) { program_.name = std::move(name); }

    // State.
    RunStatus status() const noexcept { return status_; }
    bool manual() const noexcept { return manual_; }
    const Vec3& position() const noexcept { return position_; }
    /// Per-axis velocity, mm/min (signed).
    Vec3 velocity() const;
    /// Speed along the path, mm/min (0 when not moving).
    double path_speed() const;
    double feed_override() const noexcept { return feed_override_; }
    double spindle_override() const noexcept { return spindle_override_; }
    /// Actual spindle speed, r/min (magnitude).
    double spindle_speed() const noexcept { return spindle_rpm_; }
    /// 1 forward, -1 reverse, 0 stopped.
    int spindle_direction() const noexcept { return spindle_dir_; }
    /// True while a feed move (G1/G2/G3) below Z0 is under way.
    bool cutting() const;
    /// N number of the block being executed, "0" after reset.
    std::string line_number() const;
    const std::string& program_name() const noexcept { return program_.name; }
    std::int64_t part_count() const noexcept { return part_count_; }
    int tool_number() const noexcept { return tool_; }
    const MillConfig& config() const noexcept { return config_; }

private:
    struct Segment {
        Motion motion = Motion::none;
        Vec3 start{};
        Vec3 end{};
        double length = 0;
        // arcs
        double cx = 0, cy = 0, radius = 0, a0 = 0, sweep = 0;  // sweep signed: + ccw, - cw
    };

    void begin_block();
    void finish_block();
    Vec3 point_at(double s) const;
    Vec3 direction_at(double s) const;
    double block_speed_mm_s() const;
    void run_spindle(double dt);

    Program program_;
    MillConfig config_;
    RunStatus status_ = RunStatus::free;
    bool manual_ = false;
    Vec3 position_{0, 0, 50};
    std::size_t block_ = 0;
    bool begun_ = false;
    bool rewound_ = true;  // at the program start, nothing executed yet
    Segment segment_;
    double travelled_ = 0;
    double dwell_left_ = 0;
    double feed_ = 1000;  // modal F, mm/min
    double feed_override_ = 100;
    double spindle_override_ = 100;
    double spindle_target_ = 0;  // S word, r/min
    int spindle_dir_ = 0;
    double spindle_rpm_ = 0;
    int tool_ = 1;
    std::int64_t part_count_ = 0;
};

}  // namespace nclink::sim
