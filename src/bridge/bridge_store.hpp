// What the bridge knows, shared by the NC-Link side (the follower, which
// writes) and every reader (MTConnect REST, GB/T 18759.6, SHDR, the JSON
// API): per device its model, mapping and state; per item its MTConnect
// description; and the one observation buffer with sequence numbers of
// MTConnect part 1 5.1.3 across all devices.
//
// Rules kept here (MTConnect 1.4 part 1):
//  - 5.1.3.5: an item is recorded only when its value changes;
//  - 5.1.3.7: every item starts UNAVAILABLE when its device becomes known,
//    and turns UNAVAILABLE when its adapter goes offline, except items whose
//    model gives a constant value; AVAILABILITY follows the adapter's state;
//  - sequences run across devices in arrival order.
//
// Thread-safe: every member locks one mutex. read() runs a function under
// that mutex, for readers that render a document from a consistent view;
// keep such functions short (no I/O).
#pragma once

#include "bridge/observation_buffer.hpp"

#include <nclink/json.hpp>
#include <nclink/mapping.hpp>
#include <nclink/model.hpp>
#include <nclink/result.hpp>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace nclink::bridge {

/// One item as the bridge serves it.
struct ItemEntry {
    ItemIndex index = 0;
    std::size_t device = 0;  ///< index into BridgeState::devices
    std::string nclink_id;   ///< "" for the AVAILABILITY item
    bool availability = false;
    bool constant = false;  ///< the model fixes its value: never UNAVAILABLE (5.1.3.7)
    bool setable = false;
    bool current = true;                ///< false once a newer model of its device replaced it
    MtDataItem mt;                      ///< its MTConnect description (mapping library)
    std::optional<MtDataItem> shdr_mt;  ///< how SHDR sends it, when not as `mt` (shdr_native_item)
};

/// One method call at a device, whoever made it (8.2.22-8.2.24), as its
/// Method/Status and Method/Result DTUs tell it: one entry per call,
/// updated by each DTU.
struct MethodRunEntry {
    std::uint64_t seq = 0;           ///< activity sequence of its latest change
    std::string ex;                  ///< the calling application
    std::string call;                ///< the call's @id
    std::string method;              ///< the METHOD's id
    std::string status;              ///< latest Method/Status: waiting | executing | stopped | sleep ("" = none seen)
    std::optional<double> progress;  ///< latest percent, when the adapter sends one
    std::string result;              ///< Method/Result: finished | canceled | error ("" = still running)
    Json outcome;                    ///< the result's {"code","error","reason","return"} (null until then)
    std::int64_t start_ms = 0;       ///< when its first DTU arrived
    std::int64_t time_ms = 0;        ///< when its latest DTU arrived
};

/// One Event DTU (8.2.31) of any application's registration at a device.
struct EventLogEntry {
    std::uint64_t seq = 0;  ///< activity sequence
    std::string ex;         ///< the application that registered it
    std::string event_id;   ///< the registration's id
    std::string item;       ///< the data item
    Json value;
    std::int64_t time_ms = 0;  ///< the DTU's time (arrival when it has none)
};

struct DeviceEntry {
    std::string dev;                     ///< terminal id = MTConnect Device uuid
    std::string state = "unknown";       ///< online | offline | unknown
    std::string version;                 ///< model version (Probe/Version or the model's)
    std::shared_ptr<const Model> model;  ///< null until probed
    Json model_json;                     ///< the model as the adapter sent it
    MtDevice mt;                         ///< MTConnect name/uuid/availability id
    std::string devices_xml;             ///< map_to_mtconnect of the model (its Device element)
    std::vector<ItemIndex> items;        ///< current items, AVAILABILITY first, then model order
    std::unordered_map<std::string, ItemIndex> by_nclink_id;
    std::unordered_map<std::string, ItemIndex> by_mtconnect_id;
    std::uint64_t generation = 0;  ///< changes with state, version or model
    /// The newest method runs and events, oldest first, each at most
    /// BridgeStore::activity_log_size() long (bounded: a busy machine must
    /// not grow the bridge).
    std::deque<MethodRunEntry> method_runs;
    std::deque<EventLogEntry> events;
};

/// Everything a reader sees under the lock.
struct BridgeState {
    std::deque<DeviceEntry> devices;  ///< stable addresses
    std::deque<ItemEntry> items;      ///< index = ItemIndex; stable addresses
    ObservationBuffer buffer;
    std::uint64_t device_generation = 0;  ///< grows with every device change
    std::uint64_t activity_sequence = 0;  ///< seq of the newest method-run or event change, all devices

    explicit BridgeState(std::size_t capacity) : buffer(capacity) {}
    /// A device by terminal id, MTConnect name or uuid; nullptr when unknown.
    const DeviceEntry* find_device(std::string_view name_or_uuid) const;
};

class BridgeStore {
public:
    BridgeStore(std::size_t buffer_size, std::string sender, std::uint64_t instance_id, std::size_t activity_log_size = 200);

    const std::string& sender() const noexcept { return sender_; }
    std::uint64_t instance_id() const noexcept { return instance_id_; }
    std::size_t buffer_size() const noexcept { return buffer_size_; }
    std::size_t activity_log_size() const noexcept { return activity_log_size_; }

    // ---- writers ----------------------------------------------------------
    /// Makes `dev` known (state unknown, no model yet). Idempotent.
    void add_device(const std::string& dev);
    /// Installs the model of `dev` (a Probe/Query answer): maps it, registers
    /// its items (UNAVAILABLE until a value arrives). A model equal to the
    /// installed one changes nothing. Fails when the mapping fails.
    Result<void> set_model(const std::string& dev, const Json& model_json);
    /// online / offline. Offline turns every non-constant item UNAVAILABLE and
    /// AVAILABILITY UNAVAILABLE; online turns AVAILABILITY AVAILABLE (values
    /// come back with the next Query and samples).
    void set_state(const std::string& dev, const std::string& state);
    void set_version(const std::string& dev, const std::string& version);
    /// A value of an NC-Link item (null = unreadable). Recorded when it differs
    /// from the item's current value. Unknown devices/items are ignored.
    void update(const std::string& dev, const std::string& item_id, const Json& value, std::int64_t time_ms);
    /// Several values of one device at once (one lock, one wake-up).
    struct Value {
        std::string item_id;
        Json value;
        std::int64_t time_ms = 0;
    };
    void update_many(const std::string& dev, const std::vector<Value>& values);

    /// A Method/Status (`result` empty) or Method/Result of call `call` by
    /// `ex`: updates its entry, or adds one (dropping the oldest beyond the
    /// bound). Unknown devices are ignored.
    struct MethodRunUpdate {
        std::string ex, call, method;
        std::string status;  ///< a Method/Status's status
        std::optional<double> progress;
        std::string result;  ///< a Method/Result's result
        Json outcome;        ///< and its code/error/reason/return
    };
    void record_method_run(const std::string& dev, MethodRunUpdate update, std::int64_t time_ms);
    /// An Event DTU; the oldest goes beyond the bound. Unknown devices are ignored.
    void record_event(const std::string& dev, EventLogEntry event);

    // ---- readers ----------------------------------------------------------
    template <class F>
    auto read(F&& f) const {
        std::lock_guard<std::mutex> lock(mutex_);
        return f(static_cast<const BridgeState&>(state_));
    }
    /// Waits until an observation after `after_sequence` exists, a device
    /// changed after `after_generation` or a method run or event changed
    /// after `after_activity` (default: not waited for), at most `timeout`.
    /// True when one happened.
    bool wait_for_change(std::uint64_t after_sequence, std::uint64_t after_generation, std::chrono::milliseconds timeout,
                         std::uint64_t after_activity = std::numeric_limits<std::uint64_t>::max()) const;
    /// Wakes every waiter (shutdown).
    void wake_all() const;

private:
    DeviceEntry* device_locked(const std::string& dev);
    void record_locked(ItemEntry& item, const Json& value, std::int64_t time_ms);
    void touch_locked(DeviceEntry& device);

    const std::size_t buffer_size_;
    const std::size_t activity_log_size_;
    const std::string sender_;
    const std::uint64_t instance_id_;
    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    BridgeState state_;
};

}  // namespace nclink::bridge
