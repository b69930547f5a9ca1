// PointDriver (include/nclink/point_driver.hpp): a table of declared points,
// looked up by id. A getter that throws answers 202 for its item only.
#include <nclink/point_driver.hpp>

#include <fmt/format.h>

namespace nclink {

PointValue::PointValue() : cell_(std::make_shared<Cell>()) {}
PointValue::PointValue(Json initial) : PointValue() { cell_->value = std::move(initial); }

void PointValue::set(Json value) {
    std::lock_guard<std::mutex> lock(cell_->mutex);
    cell_->value = std::move(value);
}

Json PointValue::get() const {
    std::lock_guard<std::mutex> lock(cell_->mutex);
    return cell_->value;
}

PointDriver::Point& PointDriver::Point::range(double min, double max) {
    auto& c = owner_->entries_[index_].checks;
    c.min = min;
    c.max = max;
    return *this;
}

PointDriver::Point& PointDriver::Point::one_of(std::vector<Json> values) {
    owner_->entries_[index_].checks.allowed = std::move(values);
    return *this;
}

PointValue PointDriver::Point::value() const { return owner_->entries_[index_].value; }

PointDriver::PointDriver(DriverInfo info) : info_(std::move(info)) {}

PointDriver::Point PointDriver::add(Entry entry) {
    // Declaring an id again replaces it: the last declaration wins.
    if (auto it = by_id_.find(entry.id); it != by_id_.end()) {
        entries_[it->second] = std::move(entry);
        return Point(*this, it->second);
    }
    by_id_.emplace(entry.id, entries_.size());
    entries_.push_back(std::move(entry));
    return Point(*this, entries_.size() - 1);
}

PointDriver::Point PointDriver::point(const std::string& id, Getter get) {
    Entry e;
    e.id = id;
    e.get = std::move(get);
    return add(std::move(e));
}

PointDriver::Point PointDriver::point(const std::string& id, Getter get, Setter set) {
    Entry e;
    e.id = id;
    e.get = std::move(get);
    e.set = std::move(set);
    return add(std::move(e));
}

PointDriver::Point PointDriver::value(const std::string& id, Json initial, bool settable) {
    Entry e;
    e.id = id;
    e.value = PointValue(std::move(initial));
    e.has_value = true;
    PointValue cell = e.value;
    e.get = [cell]() -> Result<Json> { return cell.get(); };
    if (settable)
        e.set = [cell](const Json& v) mutable -> Result<void> {
            cell.set(v);
            return ok_result();
        };
    return add(std::move(e));
}

std::vector<std::string> PointDriver::ids() const {
    std::vector<std::string> out;
    for (const auto& e : entries_) out.push_back(e.id);
    return out;
}

const PointChecks* PointDriver::checks(const std::string& id) const {
    const Entry* e = find(id);
    return e ? &e->checks : nullptr;
}

const PointDriver::Entry* PointDriver::find(const std::string& id) const {
    auto it = by_id_.find(id);
    return it == by_id_.end() ? nullptr : &entries_[it->second];
}

bool PointDriver::claims(std::string_view id) const { return by_id_.count(std::string(id)) > 0; }

Result<void> PointDriver::bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) {
    // A declared point's handle is its index: reads skip the id lookup. Ids
    // not declared keep no_handle, so a subclass that serves more ids in its
    // own read()/write() still sees them by id.
    for (std::size_t i = 0; i < points.size(); ++i)
        if (auto it = by_id_.find(points[i].id); it != by_id_.end()) handles[i] = it->second;
    return ok_result();
}

const PointDriver::Entry* PointDriver::find(const PointRef& point) const {
    if (point.handle < entries_.size()) return &entries_[point.handle];
    return find(point.id);
}

void PointDriver::read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Entry* e = find(points[i]);
        if (!e) {
            results[i] =
                make_error(ErrorCode::unavailable, fmt::format("driver '{}' declares no point '{}'", info_.name, points[i].id));
            continue;
        }
        try {
            results[i] = e->get();
        } catch (const std::exception& ex) {
            results[i] = make_error(ErrorCode::unavailable, fmt::format("reading {} failed: {}", e->id, ex.what()));
        } catch (...) {
            results[i] = make_error(ErrorCode::unavailable, fmt::format("reading {} failed", e->id));
        }
    }
}

Result<void> PointDriver::write(const WriteRequest& request) {
    const Entry* e = request.handle < entries_.size() ? &entries_[request.handle] : find(request.id);
    if (!e) return make_error(ErrorCode::unavailable, fmt::format("driver '{}' declares no point '{}'", info_.name, request.id));
    if (!e->set) return make_error(ErrorCode::permission_denied, fmt::format("point '{}' is read-only", request.id));
    if (request.new_value.is_null())
        return make_error(ErrorCode::unavailable,
                          fmt::format("no whole new value for '{}' (the SDK could not compute it)", request.id));
    if (auto checked = check_point_value(request.id, e->checks, request.new_value); !checked) return checked;
    try {
        return e->set(request.new_value);
    } catch (const std::exception& ex) {
        return make_error(ErrorCode::unavailable, fmt::format("setting {} failed: {}", request.id, ex.what()));
    } catch (...) {
        return make_error(ErrorCode::unavailable, fmt::format("setting {} failed", request.id));
    }
}

Result<void> check_point_value(const std::string& id, const PointChecks& checks, const Json& value) {
    if (checks.min || checks.max) {
        if (!value.is_number())
            return make_error(ErrorCode::value_type, fmt::format("{} takes a number, not {}", id, value.dump()));
        const double v = value.get<double>();
        if ((checks.min && v < *checks.min) || (checks.max && v > *checks.max))
            return make_error(ErrorCode::out_of_range, fmt::format("{} = {} is outside [{}, {}]", id, value.dump(),
                                                                   checks.min ? fmt::format("{}", *checks.min) : "-inf",
                                                                   checks.max ? fmt::format("{}", *checks.max) : "inf"));
    }
    if (!checks.allowed.empty()) {
        for (const auto& a : checks.allowed)
            if (a == value) return ok_result();
        std::string list;
        for (const auto& a : checks.allowed) list += (list.empty() ? "" : ", ") + a.dump();
        return make_error(ErrorCode::out_of_range, fmt::format("{} = {} is not one of {}", id, value.dump(), list));
    }
    return ok_result();
}

}  // namespace nclink
