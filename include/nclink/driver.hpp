// The vendor interface: how nclink reads and writes machine points and runs
// methods. A vendor implements a Driver (C++) or a plugin (C ABI,
// driver_plugin.h) and the SDK does the rest: model, Query/Set semantics,
// sampling, events, MQTT.
//
// Threading contract
// - The SDK never calls a driver from an MQTT callback thread.
// - read() and write() come from the driver's own worker thread(s), owned by
//   the SDK; sample channels read on the sampling thread (read_samples(), or
//   read() for a driver without it), still serialized with the workers. By
//   default they are serialized (one worker): the driver needs no locking of
//   its own for them. A driver whose info().concurrent is true gets
//   two workers and may be called from both at once.
// - call_method() runs on a method thread of its own, one per accepted
//   Method/Call (at most AdapterConfig::methods.max_running at once). It
//   overlaps read() and write() — a program transfer or a cycle must not stop
//   Query, Set and sampling — and other call_method() calls, whatever
//   info().concurrent says. The driver synchronizes what its methods share
//   with reads and writes itself (e.g. one mutex held for each short step,
//   never across a long wait). There is no deadline: a method runs until it
//   returns; it should call control.checkpoint() between steps so "stop",
//   "resume" and "cancel" take effect (docs/methods.md).
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
// - At Adapter::stop() running methods are cancelled and waited for
//   (methods.stop_grace, default 2 s) before close(); one still running then
//   is abandoned, like a stuck worker.
// - Events (docs/events.md) read watched items that no sample channel reads
//   with read() every events.poll_interval (default 100 ms), all of them in
//   one call. A driver that learns of changes itself may also push them:
//   Adapter::notify_value(id, whole_value) from any thread, at any time after
//   start() (it only queues the value; it never calls back into the driver).
#pragma once

#include <nclink/data_kind.hpp>
#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/log.hpp>
#include <nclink/result.hpp>
#include <nclink/sample_value.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

struct NCLINK_API DriverInfo {
    std::string name = "driver";
    std::string version = "0";
    /// true: the driver is thread-safe and may be called concurrently.
    bool concurrent = false;
};

/// What the machine link looks like from the driver's side.
enum class MachineLink { unknown, connected, disconnected };

/// Handed to open(). `config` is the driver's section of the adapter
/// configuration (or the plugin's config string parsed), `null` if none.
struct NCLINK_API DriverContext {
    Json config;
    Logger logger;
};

/// One point of a read: the model's data-item id and its data type.
struct NCLINK_API PointRef {
    std::string id;
    DataKind kind = DataKind::single;
};

/// A Set on one item, after the SDK validated it against the model.
struct NCLINK_API WriteRequest {
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

/// Given to a running method (Method/Call). Thread-safe: meant for the method
/// thread, which may call it at any rate (each call is a short lock).
class NCLINK_API MethodControl {
public:
    virtual ~MethodControl() = default;
    /// 0..100 (clamped; NaN ignored); the SDK publishes the latest value in
    /// Method/Status at its own period.
    virtual void progress(double percent) = 0;
    /// True once Method/Control "cancel" arrived (or the adapter is
    /// stopping): undo what must not stay half done and return soon. The
    /// result is then reported "canceled", whatever is returned.
    virtual bool cancelled() const = 0;
    /// Blocks while the method is paused (Method/Control "stop"; Method/Status
    /// says "stopped" meanwhile) until "resume"; returns false if cancelled.
    /// Call it between steps: a method that never does cannot be paused.
    virtual bool checkpoint() = 0;
};

class NCLINK_API Driver {
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

    /// Optional typed fast path for sample channels (docs/sampling.md,
    /// "Typed reads"). Writes the current value of points[i] into out[i] and
    /// returns true; `out` arrives with every entry null, and an entry left
    /// null is sent as null (a failed read). The default returns false, and
    /// the SDK then calls read() and converts each Json value: correct, but
    /// at high point rates most of the sampling cost is building those Json
    /// values, which a typed read skips.
    /// Called on the sampling thread, under the same rules as read():
    /// serialized with read()/write() unless info().concurrent. Used while
    /// sampling.direct_reads is on (the default); with it off, channels read
    /// through read() on a driver worker.
    /// Text and json values are borrowed: the characters must stay unchanged
    /// until read_samples() is called again (the SDK copies them before it
    /// does); storage the driver keeps for read_samples() alone satisfies
    /// this. A throw is caught; that row's values are then null.
    virtual bool read_samples(const std::vector<PointRef>& points, SampleValue* out) {
        (void)points;
        (void)out;
        return false;
    }

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

    /// Runs a METHOD of the model (method thread: see the threading contract
    /// above). `args` is the call's args object, checked against the METHOD
    /// object's declared args (defaults filled in). Returns the method's
    /// `return` value (null = none), or a table-19 error: the Method/Result is
    /// then "error" with that code, the message going to its privateInfo.
    /// Default: Unavailable (202), a driver without methods.
    virtual Result<Json> call_method(const std::string& method_id, const Json& args, MethodControl& control) {
        (void)args;
        (void)control;
        return make_error(ErrorCode::unavailable, "driver '" + info().name + "' does not implement method " + method_id);
    }

    virtual MachineLink link() const { return MachineLink::unknown; }
};

/// For the simplest drivers: implement read_one() only.
class NCLINK_API SimpleDriver : public Driver {
public:
    virtual Result<Json> read_one(const PointRef& point) = 0;

    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = read_one(points[i]);
    }
};

}  // namespace nclink
