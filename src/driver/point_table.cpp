#include "driver/point_table.hpp"

namespace nclink::driver_detail {

PointTable::PointTable(std::uint64_t generation, std::vector<PointRef> points)
    : generation_(generation), points_(std::move(points)) {
    index_.reserve(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i) index_.emplace(points_[i].id, i);
}

const PointRef* PointTable::find(std::string_view id) const {
    const auto it = index_.find(id);
    return it == index_.end() ? nullptr : &points_[it->second];
}

}  // namespace nclink::driver_detail
