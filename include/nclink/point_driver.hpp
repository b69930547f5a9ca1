// A Driver for simple machines, declared point by point: bind each model
// item id to a getter (and a setter), or to a value the firmware updates,
// with optional range or enumeration checks for Sets. The SDK does the rest
// (Query/Set semantics, sampling, events, MQTT), exactly as for a hand-written
// Driver, which it is: subclass it to add open()/close(), methods
// (run_method()) or anything else of the Driver interface.
//
//   nclink::PointDriver driver({"acme-lathe", "1.0"});
//   driver.point("x_position", [&] { return cnc.x(); });
//   driver.point("spindle_override", [&] { return cnc.override(); },
//                [&](const nclink::Json& v) { return cnc.set_override(v.get<int>()); })
//       .range(0, 150);
//   nclink::PointValue status = driver.value("status", "free");
//   ... firmware loop: status.set("running");
//
// Threading contract
// - Declare every point before Adapter::start() (run_adapter()); the table is
//   read-only afterwards (claims() and info() read it from any thread).
// - Getters and setters run where the SDK calls read() and write(): on the
//   driver's worker thread, serialized with each other (info().concurrent is
//   false unless set). They must not block for long (driver_timeout).
// - PointValue::set()/get() are thread-safe: the firmware updates a value
//   from its own thread while the SDK reads it.
#pragma once

#include <nclink/driver.hpp>

#include <functional>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace nclink {

/// A value the firmware keeps up to date and the SDK reads (and, when the
/// point is settable, writes). Thread-safe; cheap to copy (copies share it).
class NCLINK_API PointValue {
public:
    PointValue();
    explicit PointValue(Json initial);
    void set(Json value);
    Json get() const;

private:
    struct Cell {
        mutable std::mutex mutex;
        Json value;
    };
    std::shared_ptr<Cell> cell_;
};

/// What a declared point checks before a Set reaches its setter (the model's
/// own checks run first). Reads are not checked: the machine is the truth.
struct NCLINK_API PointChecks {
    std::optional<double> min, max;  ///< numbers only; out of range answers 101 Out of Range
    std::vector<Json> allowed;       ///< empty = any; otherwise the value must equal one (101)
};

class NCLINK_API PointDriver : public Driver {
public:
    using Getter = std::function<Result<Json>()>;
    using Setter = std::function<Result<void>(const Json& value)>;

    /// Declares checks on the point it was returned for.
    class NCLINK_API Point {
    public:
        /// Sets must be numbers within [min, max].
        Point& range(double min, double max);
        /// Sets must equal one of these values (e.g. table 15's STATUS words).
        Point& one_of(std::vector<Json> values);
        /// The PointValue behind a value() point (empty for getter points).
        PointValue value() const;
        operator PointValue() const { return value(); }

    private:
        friend class PointDriver;
        Point(PointDriver& owner, std::size_t index) : owner_(&owner), index_(index) {}
        PointDriver* owner_;
        std::size_t index_;
    };

    explicit PointDriver(DriverInfo info = {});

    /// A read-only point: `get` answers its current value (or an Error, e.g.
    /// unavailable while the machine cannot tell).
    Point point(const std::string& id, Getter get);
    /// A settable point: `set` receives the item's whole new value after the
    /// SDK validated the Set against the model and the point's checks.
    Point point(const std::string& id, Getter get, Setter set);
    /// Getters returning a plain value (double, int, bool, std::string, Json).
    template <class F, class = std::enable_if_t<!std::is_convertible_v<F, Getter>>>
    Point point(const std::string& id, F get) {
        return point(id, Getter([get]() -> Result<Json> { return Json(get()); }));
    }
    template <class F, class = std::enable_if_t<!std::is_convertible_v<F, Getter>>>
    Point point(const std::string& id, F get, Setter set) {
        return point(id, Getter([get]() -> Result<Json> { return Json(get()); }), std::move(set));
    }
    /// A point backed by a PointValue the firmware updates; `settable`: a Set
    /// stores the new value there (the firmware reads it back with get()).
    Point value(const std::string& id, Json initial = nullptr, bool settable = false);

    /// The ids declared, in declaration order.
    std::vector<std::string> ids() const;
    /// The checks of a declared point (nullptr if not declared).
    const PointChecks* checks(const std::string& id) const;

    // ---- Driver ----
    DriverInfo info() const override { return info_; }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override;
    Result<void> write(const WriteRequest& request) override;
    /// Gives each declared point its index as handle (reads and writes skip
    /// the id lookup); other ids keep no_handle. A subclass that overrides
    /// bind() calls this one and leaves the declared points' handles alone.
    Result<void> bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) override;
    /// A declared point is the driver's, also when the model gives it a
    /// fixed value or lists it in configs.
    bool claims(std::string_view id) const override;

private:
    struct Entry {
        std::string id;
        Getter get;
        Setter set;
        PointChecks checks;
        PointValue value;
        bool has_value = false;
    };
    Point add(Entry entry);
    const Entry* find(const std::string& id) const;
    const Entry* find(const PointRef& point) const;

    DriverInfo info_;
    std::vector<Entry> entries_;
    std::unordered_map<std::string, std::size_t> by_id_;
};

/// Checks `value` against `checks`: ok, or out_of_range (101) with a message
/// naming the point, the value and what is allowed.
NCLINK_API Result<void> check_point_value(const std::string& id, const PointChecks& checks, const Json& value);

}  // namespace nclink
