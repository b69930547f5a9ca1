// The handles one bind() gave (driver.hpp, "Handles"): every point of one
// installed model, looked up by id once per model (when a request names an
// id, when a channel or an events poll is planned), never per read.
// Immutable once built; shared by the model snapshot and the runner.
#pragma once

#include <nclink/driver.hpp>

#include <cstdint>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace nclink::driver_detail {

class PointTable {
public:
    /// `generation` numbers the bind() (1, 2, ...); 0 is never a bind's.
    PointTable(std::uint64_t generation, std::vector<PointRef> points);
    PointTable(const PointTable&) = delete;  // the index points into points_
    PointTable& operator=(const PointTable&) = delete;

    std::uint64_t generation() const noexcept { return generation_; }
    /// The bound point of `id`, or nullptr when the model's bind() did not
    /// include it (an SDK-held item, another device's, an unknown id).
    const PointRef* find(std::string_view id) const;
    const std::vector<PointRef>& points() const noexcept { return points_; }

private:
    const std::uint64_t generation_;
    const std::vector<PointRef> points_;
    std::unordered_map<std::string_view, std::size_t> index_;
};

/// Generation of PointRefs that come from no table (built by hand, e.g. in
/// tests): the runner resolves them by id against the current binding.
inline constexpr std::uint64_t unbound = 0;

}  // namespace nclink::driver_detail
