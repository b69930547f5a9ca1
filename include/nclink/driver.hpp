// The vendor interface: how nclink reads and writes machine points and runs
// methods. A vendor implements a Driver (C++) or writes a plugin (C ABI,
// driver_plugin.h); the SDK does the rest: model, Query/Set semantics,
// sampling, events, MQTT.
//
// Handles (bind)
// - bind() is called once per installed model: at start() and after every
//   model change (Probe/Set), with every point the driver is asked about:
//   each data item the SDK does not hold itself, and each METHOD. The driver
//   answers a handle per point: a number of its own (an index into its
//   table, say), no_handle (identify it by id, today's behaviour, the
//   default), or not_served (the SDK then answers the point 202 Unavailable
//   without calling the driver). From then on every PointRef the driver gets
//   (read(), read_samples(), WriteRequest, run_method()) carries that handle.
//   Ids are resolved to handles once per model, never per read.
// - Once bind() returned, no call passes a handle of an earlier bind(): a
//   call that was prepared against the previous model is re-resolved by id
//   (points the new model does not have answer 202 without a driver call).
// - An error from bind() refuses the model: start() fails with it, or the
//   Probe/Set is answered with its code (the model in force stays).
//
// Errors and reasons (docs/porting-guide.md §5, docs/wire.md "Vendor errors")
// - Every failure the driver reports (a read of one point, a write, a method,
//   open(), bind()) is an Error: a table-19 code and the vendor's reason in
//   `message`. Both reach the wire: `error`/`reason` from the code, the
//   vendor's words in the item's privateInfo {"message": ...}. A vendor code
//   below 0 (vendor_error(), table 19 leaves those to the user) goes on the
//   wire as is with the vendor's words as `reason`; a positive code table 19
//   does not define is answered 202 with "vendor error <n>: ..." as message.
//
// The machine link (link())
// - link() says whether the machine (the CNC behind the driver) is reachable.
//   While it answers disconnected, the SDK calls neither read() nor
//   read_samples() nor write(): items answer 202 Unavailable with privateInfo
//   "machine disconnected: <reason>", sample values are null, and
//   AdapterStats::machine_link shows the state and reason. It is asked before
//   every batch (a Query, a Set item, a sampling tick, an events poll), so it
//   must be cheap (an atomic, no machine I/O), thread-safe, and never block.
//   Default: unknown (the SDK calls the driver as usual).
//
// Threading contract
// - The SDK never calls a driver from an MQTT callback thread.
// - read() and write() come from the driver's own worker thread(s), owned by
//   the SDK; sample channels read on the sampling thread (read_samples(), or
//   read() for a driver without it), still serialized with the workers. By
//   default they are serialized (one worker): the driver needs no locking of
//   its own for them. While a channel of at most 4 ms finds the driver held
//   by a request, the sampling thread also runs the requests' read() calls
//   (docs/sampling.md, "The sampling thread reads for the requests"): still
//   one call at a time. A driver whose info().concurrent is true gets
//   two workers and may be called from both at once.
// - bind() runs on the thread installing the model (the start() thread, or
//   the request worker accepting a Probe/Set), exclusively: no read(),
//   read_samples() or write() runs meanwhile, also on a concurrent driver
//   (run_method() may: methods keep running across a model change). It waits
//   at most driver_timeout for a running call to finish, else the model is
//   refused with Timeout (203).
// - run_method() runs on a method thread of its own, one per accepted
//   Method/Call (at most AdapterConfig::methods.max_running at once). It
//   overlaps read() and write() — a program transfer or a cycle must not stop
//   Query, Set and sampling — and other run_method() calls, whatever
//   info().concurrent says. The driver synchronizes what its methods share
//   with reads and writes itself (e.g. one mutex held for each short step,
//   never across a long wait). There is no deadline: a method runs until it
//   returns; it should call control.checkpoint() between steps so "stop",
//   "resume" and "cancel" take effect (docs/methods.md).
// - open() runs on the thread calling Adapter::start(), before any other call
//   (bind() comes right after it); close() on the thread calling
//   Adapter::stop(), after the last one (not called when start() fails after
//   open(), nor when a stuck worker had to be abandoned at shutdown).
// - info(), claims() and link() may be called from any SDK thread at any
//   time, also while read() runs: answer them from constant data (link():
//   from an atomic the driver keeps up to date).
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

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

struct DataObject;  // model.hpp
struct Method;      // model.hpp

struct NCLINK_API DriverInfo {
    std::string name = "driver";
    std::string version = "0";
    /// true: the driver is thread-safe and may be called concurrently.
    bool concurrent = false;
};

/// What the machine link looks like from the driver's side.
enum class MachineLink { unknown, connected, disconnected };

/// "unknown", "connected", "disconnected".
constexpr std::string_view to_string(MachineLink link) noexcept {
    switch (link) {
        case MachineLink::connected: return "connected";
        case MachineLink::disconnected: return "disconnected";
        default: return "unknown";
    }
}

/// link(): the state and, when disconnected, why (the vendor's words: "CNC
/// cable unplugged", "controller in E-stop"), shown in the statistics and in
/// the privateInfo of the items answered 202 meanwhile.
struct NCLINK_API MachineLinkStatus {
    MachineLink state = MachineLink::unknown;
    std::string reason;
};

/// Handed to open(). `config` is the driver's section of the adapter
/// configuration (or the plugin's config string parsed), `null` if none.
struct NCLINK_API DriverContext {
    Json config;
    Logger logger;
};

/// The driver's own number for a point, chosen in bind(): opaque to the SDK
/// (an index into the driver's table is the usual choice).
using PointHandle = std::uint64_t;
/// bind() answer: the driver has no handle for the point and identifies it
/// by `id` (the default: drivers that ignore handles keep working).
inline constexpr PointHandle no_handle = ~PointHandle{0};
/// bind() answer: the driver does not serve the point. The SDK answers it
/// 202 Unavailable itself (null in samples) and never passes it to the driver.
inline constexpr PointHandle not_served = ~PointHandle{0} - 1;

/// One point the SDK asks bind() about, with what the model says of it. The
/// strings are copies; `object`/`method_object` point into the model being
/// installed (include <nclink/model.hpp> to use them) and are valid during
/// bind() only; they are null for a plugin (driver_plugin.h passes the
/// strings).
struct NCLINK_API BindPoint {
    std::string id;
    DataKind kind = DataKind::single;  ///< the model's `datatype`
    bool method = false;               ///< a METHOD object (run_method()), not a data item
    std::string type;                  ///< the model's `type` ("POSITION", "STATUS", "METHOD"...)
    std::string name;
    std::string units;
    std::string path;  ///< component path, "/MACHINE/AXIS@X/POSITION" (docs/model.md)
    bool setable = false;
    bool config = false;                    ///< listed in a `configs` array (a claimed config object)
    const DataObject* object = nullptr;     ///< the whole data object (null for methods)
    const Method* method_object = nullptr;  ///< the whole METHOD object (null for data items)
};

/// One point of a read: the model's data-item id, its data type and the
/// handle bind() gave it (no_handle when the driver gave none).
struct NCLINK_API PointRef {
    std::string id;
    DataKind kind = DataKind::single;
    PointHandle handle = no_handle;
};

/// A Set on one item, after the SDK validated it against the model.
struct NCLINK_API WriteRequest {
    std::string id;
    DataKind kind = DataKind::single;
    /// What bind() answered for the item (no_handle when the driver gave none).
    PointHandle handle = no_handle;
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

    /// The points of a newly installed model (see "Handles" above):
    /// `handles[i]` answers `points[i]` and arrives as no_handle. Set an
    /// entry to a number of the driver's own (any value but no_handle and
    /// not_served), or to not_served. An error refuses the model (its code
    /// and message reach the Probe/Set answer, or fail start()). A throw is
    /// caught and refuses the model (202). Default: every point by id.
    virtual Result<void> bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) {
        (void)points;
        (void)handles;
        return ok_result();
    }

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

    /// Runs a METHOD of the model (Method/Call; method thread: see the
    /// threading contract above). `method` carries the METHOD's id and the
    /// handle bind() gave it (no_handle when none), so a driver dispatches on
    /// either. `args` is the call's args object, checked against the METHOD
    /// object's declared args (defaults filled in). Returns the method's
    /// `return` value (null = none), or a table-19 error: the Method/Result is
    /// then "error" with that code, the message going to its privateInfo.
    /// Default: Unavailable (202), a driver without methods.
    virtual Result<Json> run_method(const PointRef& method, const Json& args, MethodControl& control) {
        (void)args;
        (void)control;
        return make_error(ErrorCode::unavailable, "driver '" + info().name + "' does not implement method " + method.id);
    }

    /// The machine link (see "The machine link" above): cheap, thread-safe,
    /// never blocking. Default: unknown.
    virtual MachineLinkStatus link() const { return {}; }
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
