// A driver's read and write as a test writes them: single points by id, one
// result per point (each "not read" until the driver says otherwise).
#pragma once

#include <nclink/driver.hpp>

#include <string>
#include <vector>

namespace nclink::test {

inline std::vector<Result<Json>> read_points(Driver& driver, const std::vector<std::string>& ids) {
    std::vector<PointRef> points;
    for (const auto& id : ids) points.push_back(PointRef{id, DataKind::single});
    std::vector<Result<Json>> results(points.size(), make_error(ErrorCode::unavailable, "not read"));
    driver.read(points, results);
    return results;
}

inline Result<void> write_point(Driver& driver, const std::string& id, Json value) {
    WriteRequest w;
    w.id = id;
    w.new_value = std::move(value);
    return driver.write(w);
}

}  // namespace nclink::test
