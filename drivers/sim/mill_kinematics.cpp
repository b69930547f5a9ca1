#include "mill_kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace nclink::sim {

namespace {

constexpr double two_pi = 6.283185307179586;

double distance(const Vec3& a, const Vec3& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

const char* to_string(RunStatus status) noexcept {
    switch (status) {
        case RunStatus::running: return "running";
        case RunStatus::free: return "free";
        case RunStatus::holding: return "holding";
    }
    return "free";
}

MillMachine::MillMachine(Program program, MillConfig config, bool autostart) : program_(std::move(program)), config_(config) {
    if (autostart) status_ = RunStatus::running;
}

Result<void> MillMachine::cycle_start() {
    if (manual_) return make_error(ErrorCode::permission_denied, "cycle start refused: work mode is manual");
    status_ = RunStatus::running;
    return ok_result();
}

void MillMachine::feed_hold() {
    if (status_ == RunStatus::running) status_ = RunStatus::holding;
}

void MillMachine::reset() {
    status_ = RunStatus::free;
    block_ = 0;
    begun_ = false;
    rewound_ = true;
    travelled_ = 0;
    dwell_left_ = 0;
    segment_ = Segment{};
    spindle_dir_ = 0;
}

Result<void> MillMachine::set_feed_override(double percent) {
    if (!(percent >= 0 && percent <= config_.max_override))
        return make_error(ErrorCode::out_of_range,
                          "feed override must be 0.." + std::to_string(static_cast<int>(config_.max_override)));
    feed_override_ = percent;
    return ok_result();
}

Result<void> MillMachine::set_spindle_override(double percent) {
    if (!(percent >= 0 && percent <= config_.max_override))
        return make_error(ErrorCode::out_of_range,
                          "spindle override must be 0.." + std::to_string(static_cast<int>(config_.max_override)));
    spindle_override_ = percent;
    return ok_result();
}

void MillMachine::set_manual(bool manual) {
    manual_ = manual;
    if (manual && status_ != RunStatus::free) status_ = RunStatus::free;
}

double MillMachine::block_speed_mm_s() const {
    if (segment_.motion == Motion::rapid)  // rapids follow the feed override too, capped at 100 %
        return config_.rapid_mm_min * std::min(feed_override_, 100.0) / 100.0 / 60.0;
    return feed_ * feed_override_ / 100.0 / 60.0;
}

void MillMachine::run_spindle(double dt) {
    const double target = spindle_dir_ == 0 ? 0.0 : std::min(spindle_target_ * spindle_override_ / 100.0, config_.spindle_max_rpm);
    const double step = config_.spindle_accel_rpm_s * dt;
    if (spindle_rpm_ < target) spindle_rpm_ = std::min(target, spindle_rpm_ + step);
    else spindle_rpm_ = std::max(target, spindle_rpm_ - step);
}

void MillMachine::begin_block() {
    const Block& b = program_.blocks[block_];
    begun_ = true;
    rewound_ = false;
    travelled_ = 0;
    dwell_left_ = b.dwell_s;
    if (b.feed) feed_ = *b.feed;
    if (b.spindle) spindle_target_ = *b.spindle;
    if (b.spindle_dir) spindle_dir_ = *b.spindle_dir;
    if (b.tool) tool_ = *b.tool;
    if (b.tool_change) dwell_left_ += config_.tool_change_s;
    segment_ = Segment{};
    if (!b.moves()) return;
    Segment s;
    s.motion = b.motion;
    s.start = position_;
    s.end = {b.x.value_or(position_[0]), b.y.value_or(position_[1]), b.z.value_or(position_[2])};
    if (b.motion == Motion::arc_cw || b.motion == Motion::arc_ccw) {
        s.cx = position_[0] + b.i.value_or(0);
        s.cy = position_[1] + b.j.value_or(0);
        s.radius = std::hypot(position_[0] - s.cx, position_[1] - s.cy);
        s.a0 = std::atan2(position_[1] - s.cy, position_[0] - s.cx);
        const double a1 = std::atan2(s.end[1] - s.cy, s.end[0] - s.cx);
        double sweep = b.motion == Motion::arc_ccw ? a1 - s.a0 : s.a0 - a1;
        while (sweep <= 1e-9) sweep += two_pi;  // same start and end: a full circle
        while (sweep > two_pi + 1e-9) sweep -= two_pi;
        s.sweep = b.motion == Motion::arc_ccw ? sweep : -sweep;
        const double dz = s.end[2] - s.start[2];
        s.length = std::hypot(s.radius * sweep, dz);
        if (s.radius < 1e-9) s.motion = Motion::linear;  // degenerate: treat as a line
    }
    if (s.motion == Motion::rapid || s.motion == Motion::linear) s.length = distance(s.start, s.end);
    segment_ = s;
}

Vec3 MillMachine::point_at(double s) const {
    const Segment& g = segment_;
    const double f = g.length > 0 ? std::clamp(s / g.length, 0.0, 1.0) : 1.0;
    if (g.motion == Motion::arc_cw || g.motion == Motion::arc_ccw) {
        const double a = g.a0 + g.sweep * f;
        return {g.cx + g.radius * std::cos(a), g.cy + g.radius * std::sin(a), g.start[2] + (g.end[2] - g.start[2]) * f};
    }
    return {g.start[0] + (g.end[0] - g.start[0]) * f, g.start[1] + (g.end[1] - g.start[1]) * f,
            g.start[2] + (g.end[2] - g.start[2]) * f};
}

Vec3 MillMachine::direction_at(double s) const {
    const Segment& g = segment_;
    if (g.length <= 0) return {0, 0, 0};
    if (g.motion == Motion::arc_cw || g.motion == Motion::arc_ccw) {
        const double a = g.a0 + g.sweep * std::clamp(s / g.length, 0.0, 1.0);
        // d(point)/ds: the tangent scaled so that its length is 1.
        return {-g.radius * g.sweep * std::sin(a) / g.length, g.radius * g.sweep * std::cos(a) / g.length,
                (g.end[2] - g.start[2]) / g.length};
    }
    return {(g.end[0] - g.start[0]) / g.length, (g.end[1] - g.start[1]) / g.length, (g.end[2] - g.start[2]) / g.length};
}

void MillMachine::finish_block() {
    if (segment_.motion != Motion::none) position_ = point_at(segment_.length);  // never jump to the programmed end
    const bool end = program_.blocks[block_].end;
    begun_ = false;
    segment_ = Segment{};
    if (end) {
        ++part_count_;
        block_ = 0;  // production loop: the next cycle starts at once
    } else {
        block_ = (block_ + 1) % program_.blocks.size();
    }
}

void MillMachine::advance(double dt) {
    std::size_t idle_blocks = 0;  // blocks finished without using time
    while (dt > 0) {
        if (status_ != RunStatus::running) {
            run_spindle(dt);
            return;
        }
        if (!begun_) begin_block();
        bool used_time = false;
        if (dwell_left_ > 0) {
            const double use = std::min(dt, dwell_left_);
            run_spindle(use);
            dwell_left_ -= use;
            dt -= use;
            used_time = true;
            if (dwell_left_ > 0) return;
        }
        if (segment_.motion != Motion::none && travelled_ < segment_.length) {
            const double v = block_speed_mm_s();
            if (v <= 0) {  // feed override 0: the program stands still
                run_spindle(dt);
                return;
            }
            const double need = (segment_.length - travelled_) / v;
            if (need > dt) {
                travelled_ += v * dt;
                position_ = point_at(travelled_);
                run_spindle(dt);
                return;
            }
            run_spindle(need);
            dt -= need;
            used_time = true;
        }
        finish_block();
        idle_blocks = used_time ? 0 : idle_blocks + 1;
        if (idle_blocks > program_.blocks.size()) return;  // a program that takes no time
    }
}

Vec3 MillMachine::velocity() const {
    const double v = path_speed();
    if (v <= 0) return {0, 0, 0};
    const Vec3 d = direction_at(travelled_);
    return {d[0] * v, d[1] * v, d[2] * v};
}

double MillMachine::path_speed() const {
    if (status_ != RunStatus::running || !begun_ || dwell_left_ > 0 || segment_.motion == Motion::none ||
        travelled_ >= segment_.length)
        return 0;
    return block_speed_mm_s() * 60.0;
}

bool MillMachine::cutting() const { return path_speed() > 0 && segment_.motion != Motion::rapid && position_[2] < 0; }

std::string MillMachine::line_number() const {
    if (rewound_) return "0";
    return std::to_string(program_.blocks[block_].number);
}

}  // namespace nclink::sim
