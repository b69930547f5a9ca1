// The driver of your machine: one line per item of model.json that the
// machine answers (the SDK answers the configs itself). Replace the values
// by calls into your controller, e.g.
//   d->point("x_position", [&cnc] { return cnc.read_axis(0); });
//   d->point("feed_override", [&cnc] { return cnc.feed(); },
//            [&cnc](const nclink::Json& v) { cnc.set_feed(v.get<int>()); return nclink::ok_result(); })
//       .range(0, 150);
// Getters and setters run on the SDK's driver thread, one at a time.
#pragma once

#include <nclink/point_driver.hpp>

#include <memory>

inline std::shared_ptr<nclink::PointDriver> make_machine_driver() {
    auto d = std::make_shared<nclink::PointDriver>(nclink::DriverInfo{"my-machine", "0.1.0"});
    // Values your firmware keeps up to date: keep the PointValue that
    // d->value() returns and call .set("running") from the firmware's loop.
    d->value("status", "free");
    d->value("alarm", nclink::Json{{"number", "0"}, {"text", "no alarm"}});
    return d;
}
