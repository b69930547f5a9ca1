// The vendor interface: how nclink reads and writes machine points and runs
// methods. A vendor implements a Driver (C++) or a plugin (C ABI,
// driver_plugin.h) and the SDK does the rest: model, Query/Set semantics,
// sampling, events, MQTT.
//
// Threading contract
// - The SDK never calls a driver from an MQTT callback thread.
// - read(), write() and call_method() come from the driver's own worker
//   thread(s), owned by the SDK. By default they are serialized (one worker):
//   the driver needs no locking of its own for them. A driver whose
//   info().concurrent is true gets two workers and may be called from both at
//   once.
// - open() runs on the thread calling Adapter::start(), before any other call;
//   close() on the thread calling Adapter::stop(), after the last one (not
//   called when start() fails after open(), nor when a stuck worker had to be
//   abandoned at shutdown).
// - info() and claims() may be called from any SDK thread at any time, also
//   while read() runs: answer them from constant data.
// - read() and write() have a deadline (AdapterConfig::driver_timeout, default
//   1000 ms). A call that overruns it answers Timeout (203) for its items; the
//   SDK does not wait for the driver to return, but it does not start a second
//   call while one is running on a serialized driver either, so later calls
//   queue (and time out) behind a stuck one.
// - Methods (call_method) are served once the methods module lands; until then
//   the adapter answers Method/Call with NG 202.
#pragma once

#include <nclink/data_kind.hpp>
#include <nclink/json.hpp>
#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

struct DriverInfo {
    std::string name = "driver";
    std::string version = "0";
    /// true: the driver is thread-safe and may be called concurrently.
    bool concurrent = false;
};

/// What the machine link looks like from the driver's side.
enum class MachineLink { unknown, connected, disconnected };

/// Handed to open(). `config` is the driver's section of the adapter
/// configuration (or the plugin's config string parsed), `null` if none.
struct DriverContext {
    Json config;
    Logger logger;
};

/// One point of a read: the model's data-item id and its data type.
struct PointRef {
    std::string id;
    DataKind kind = DataKind::single;
};

/// A Set on one item, after the SDK validated it against the model.
struct WriteRequest {
    std::string id;
    DataKind kind = DataKind::single;
    /// The item's `params` from the Set DTU, as sent (operation, key, index,
    /// offset, length, value...). Drivers with granular writes use this.
    Json params;
    /// The item's whole value after the operation, when the SDK could compute
    /// it (it read the current value and applied the operation): drivers that
    /// only write whole items use this. null when not computed.
    Json new_value;
};

/// Given to a running method (Method/Call). Thread: the method runs on a
/// driver worker; these calls may be made from it at any rate.
class MethodControl {
public:
    virtual ~MethodControl() = default;
    /// 0..100; the SDK publishes Method/Status at its own period.
    virtual void progress(double percent) = 0;
    /// True once Method/Control "cancel" arrived: return soon (any result).
    virtual bool cancelled() const = 0;
    /// Blocks while the method is paused (Method/Control "stop") until
    /// "resume"; returns false if cancelled. Call it between steps.
    virtual bool checkpoint() = 0;
};

class Driver {
public:
    virtual ~Driver() = default;

    virtual DriverInfo info() const { return {}; }

    /// Connect to the machine. An error stops the adapter from starting.
    virtual Result<void> open(const DriverContext& context) {
        (void)context;
        return ok_result();
    }
    virtual void close() {}

    /// Required. Reads the current value of every point: results[i] answers
    /// points[i]. An item the machine cannot give now answers Unavailable
    /// (202); other failures any table-19 code with a detail message.
    /// `results` arrives sized to points.size(), every entry 202.
    virtual void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) = 0;

    /// Items whose value the SDK holds itself — data objects with a fixed
    /// `value` in the model and configuration objects — are answered from the
    /// SDK's value store (settable ones are stored and persisted by the SDK)
    /// unless the driver claims them here. Every other data item is read from
    /// the driver. Default: claims none.
    virtual bool claims(std::string_view id) const {
        (void)id;
        return false;
    }

    /// Writes one item. Default: Permission Denied (301), a read-only driver.
    virtual Result<void> write(const WriteRequest& request) {
        return make_error(ErrorCode::permission_denied, "driver '" + info().name + "' is read-only, cannot set " + request.id);
    }

    /// Runs a METHOD of the model. Returns the method's `return` value.
    /// Default: Node not exists (401).
    virtual Result<Json> call_method(const std::string& method_id, const Json& args, MethodControl& control) {
        (void)args;
        (void)control;
        return make_error(ErrorCode::node_not_exists, "driver '" + info().name + "' has no method " + method_id);
    }

    virtual MachineLink link() const { return MachineLink::unknown; }
};

/// For the simplest drivers: implement read_one() only.
class SimpleDriver : public Driver {
public:
    virtual Result<Json> read_one(const PointRef& point) = 0;

    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = read_one(points[i]);
    }
};

}  // namespace nclink
