// The nclink driver of the ACME 2-axis lathe: one line per model item. The
// SDK does Query/Set semantics, sampling, events and MQTT; the range and
// enumeration checks below answer a bad Set before the machine sees it.
#pragma once

#include "lathe_machine.hpp"

#include <nclink/point_driver.hpp>

namespace acme {

inline std::shared_ptr<nclink::PointDriver> make_lathe_driver(LatheMachine& cnc) {
    auto d = std::make_shared<nclink::PointDriver>(nclink::DriverInfo{"acme-lathe", "1.0.0"});
    d->point("x_position", [&cnc] { return cnc.x(); });
    d->point("z_position", [&cnc] { return cnc.z(); });
    d->point("x_load", [&cnc] { return cnc.running() ? 35.0 : 0.0; });
    d->point("z_load", [&cnc] { return cnc.running() ? 20.0 : 0.0; });
    d->point("spindle_speed", [&cnc] { return cnc.spindle_speed(); });
    d->point("spindle_load", [&cnc] { return cnc.running() ? 42.0 : 0.0; });
    d->point("spindle_mode", [&cnc] { return cnc.running() ? "forward" : "stop"; });
    d->point(
         "spindle_override", [&cnc] { return cnc.spindle_override(); },
         [&cnc](const nclink::Json& v) {
             cnc.set_spindle_override(v.get<int>());
             return nclink::ok_result();
         })
        .range(50, 120);
    d->point(
         "feed_override", [&cnc] { return cnc.feed_override(); },
         [&cnc](const nclink::Json& v) {
             cnc.set_feed_override(v.get<int>());
             return nclink::ok_result();
         })
        .range(0, 150);
    d->point("status", [&cnc] { return cnc.running() ? "running" : "free"; });
    d->value("work_mode", "auto", true).one_of({"manual", "auto"});
    d->value("program", "O1000");
    d->point("line_number", [&cnc] { return std::to_string(cnc.line()); });
    d->point("part_count", [&cnc] { return std::to_string(cnc.parts()); });
    d->value("alarm", nclink::Json{{"number", "0"}, {"text", "no alarm"}});
    return d;
}

}  // namespace acme
