#include "bridge/bridge_store.hpp"

#include "bridge/mtconnect_documents.hpp"
#include "bridge/shdr.hpp"

#include <algorithm>

namespace nclink::bridge {

const DeviceEntry* BridgeState::find_device(std::string_view name_or_uuid) const {
    for (const auto& d : devices)
        if (d.dev == name_or_uuid) return &d;
    for (const auto& d : devices)
        if (d.model && (d.mt.name == name_or_uuid || d.mt.uuid == name_or_uuid)) return &d;
    return nullptr;
}

BridgeStore::BridgeStore(std::size_t buffer_size, std::string sender, std::uint64_t instance_id, std::size_t activity_log_size)
    : buffer_size_(buffer_size),
      activity_log_size_(activity_log_size),
      sender_(std::move(sender)),
      instance_id_(instance_id),
      state_(buffer_size) {}

DeviceEntry* BridgeStore::device_locked(const std::string& dev) {
    for (auto& d : state_.devices)
        if (d.dev == dev) return &d;
    return nullptr;
}

void BridgeStore::touch_locked(DeviceEntry& device) { device.generation = ++state_.device_generation; }

void BridgeStore::record_locked(ItemEntry& item, const Json& value, std::int64_t time_ms) {
    const auto& latest = state_.buffer.latest();
    if (item.index < latest.size() && latest[item.index] && latest[item.index]->value == value) return;
    state_.buffer.append(item.index, value, time_ms);
}

void BridgeStore::add_device(const std::string& dev) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (device_locked(dev)) return;
        DeviceEntry d;
        d.dev = dev;
        d.mt.uuid = dev;
        d.mt.name = dev;
        state_.devices.push_back(std::move(d));
        touch_locked(state_.devices.back());
    }
    changed_.notify_all();
}

Result<void> BridgeStore::set_model(const std::string& dev, const Json& model_json) {
    // Parse and map outside the lock: both are pure.
    auto loaded = parse_model(model_json.dump(-1, ' ', false, Json::error_handler_t::replace));
    if (!loaded.ok()) {
        std::string why = "model of " + dev + " does not load";
        for (const auto& p : loaded.problems)
            if (p.severity == Severity::fatal) {
                why += ": " + p.message;
                break;
            }
        return make_error(ErrorCode::syntax_error, why);
    }
    const Model& model = *loaded.model;
    MappingOptions options;
    options.sender = sender_;
    options.instance_id = instance_id_;
    if (model.devices().size() == 1) options.dev_uuid = dev;
    // Two adapters built from one model have the same ids; the all-device
    // documents need unique ones (IDType is xs:ID). The terminal id is unique
    // on the broker, and a prefix that is always there keeps every id stable
    // whichever other adapters come and go (docs/bridge.md "Identifiers").
    options.id_prefix = dev;
    auto mapping = mtconnect_mapping(model, options);
    if (!mapping) return std::move(mapping).error();
    auto document = map_to_mtconnect(model, options);
    if (!document) return std::move(document).error();
    if (mapping->devices().empty()) return make_error(ErrorCode::parameter_missing, "model of " + dev + " has no device");

    {
        std::lock_guard<std::mutex> lock(mutex_);
        DeviceEntry* device = device_locked(dev);
        if (!device) {
            DeviceEntry d;
            d.dev = dev;
            state_.devices.push_back(std::move(d));
            device = &state_.devices.back();
        }
        if (device->model && device->model_json == model_json) return ok_result();
        std::size_t device_index = 0;
        while (&state_.devices[device_index] != device) ++device_index;
        for (ItemIndex old : device->items) state_.items[old].current = false;
        device->items.clear();
        device->by_nclink_id.clear();
        device->by_mtconnect_id.clear();
        device->model = loaded.model;
        device->model_json = model_json;
        device->mt = mapping->devices().front();
        device->devices_xml = std::move(document->xml);
        if (device->version.empty()) {
            const Device* d = model.devices().empty() ? nullptr : &model.devices().front();
            device->version = d ? d->version : model.root().version;
        }
        const bool online = device->state == "online";
        const std::int64_t now = now_ms();

        auto add_item = [&](ItemEntry entry) -> ItemEntry& {
            entry.index = static_cast<ItemIndex>(state_.items.size());
            entry.device = device_index;
            state_.items.push_back(std::move(entry));
            ItemEntry& item = state_.items.back();
            device->items.push_back(item.index);
            if (!item.nclink_id.empty()) device->by_nclink_id[item.nclink_id] = item.index;
            device->by_mtconnect_id[item.mt.id] = item.index;
            return item;
        };
        ItemEntry avail;
        avail.availability = true;
        avail.mt = availability_item(device->mt, device->mt.id);
        ItemEntry& a = add_item(std::move(avail));
        record_locked(a, online ? Json("AVAILABLE") : Json(), now);
        for (const MtDataItem& mt : mapping->items()) {
            if (mt.target != MtTarget::data_item && mt.target != MtTarget::fallback) continue;
            ItemEntry entry;
            entry.nclink_id = mt.item_id;
            entry.mt = mt;
            entry.shdr_mt = shdr_native_item(mt);
            const DataObject* object = model.data_object(mt.item_id);
            entry.setable = object && object->setable;
            entry.constant = object && object->value.has_value();
            ItemEntry& item = add_item(std::move(entry));
            record_locked(item, item.constant ? *object->value : Json(), now);
        }
        touch_locked(*device);
    }
    changed_.notify_all();
    return ok_result();
}

void BridgeStore::set_state(const std::string& dev, const std::string& state) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        DeviceEntry* device = device_locked(dev);
        if (!device || device->state == state) return;
        device->state = state;
        const std::int64_t now = now_ms();
        for (ItemIndex index : device->items) {
            ItemEntry& item = state_.items[index];
            if (item.availability) {
                record_locked(item, state == "online" ? Json("AVAILABLE") : Json(), now);
            } else if (state != "online" && !item.constant) {
                record_locked(item, Json(), now);
            }
        }
        touch_locked(*device);
    }
    changed_.notify_all();
}

void BridgeStore::set_version(const std::string& dev, const std::string& version) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        DeviceEntry* device = device_locked(dev);
        if (!device || device->version == version) return;
        device->version = version;
        touch_locked(*device);
    }
    changed_.notify_all();
}

void BridgeStore::update(const std::string& dev, const std::string& item_id, const Json& value, std::int64_t time_ms) {
    update_many(dev, {Value{item_id, value, time_ms}});
}

void BridgeStore::update_many(const std::string& dev, const std::vector<Value>& values) {
    bool any = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        DeviceEntry* device = device_locked(dev);
        // A sample still in flight when the adapter said "offline" must not
        // turn an UNAVAILABLE item back into a value: every item of an
        // unavailable device stays UNAVAILABLE until it is online again.
        if (!device || device->state == "offline") return;
        const std::uint64_t before = state_.buffer.next_sequence();
        for (const auto& v : values) {
            auto it = device->by_nclink_id.find(v.item_id);
            if (it == device->by_nclink_id.end()) continue;
            ItemEntry& item = state_.items[it->second];
            if (item.constant) continue;
            record_locked(item, v.value, v.time_ms);
        }
        any = state_.buffer.next_sequence() != before;
    }
    if (any) changed_.notify_all();
}

void BridgeStore::record_method_run(const std::string& dev, MethodRunUpdate update, std::int64_t time_ms) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        DeviceEntry* device = device_locked(dev);
        if (!device || activity_log_size_ == 0) return;
        auto& runs = device->method_runs;
        // Newest last: the call an update belongs to is usually near the end.
        auto it = std::find_if(runs.rbegin(), runs.rend(),
                               [&](const MethodRunEntry& r) { return r.call == update.call && r.ex == update.ex; });
        MethodRunEntry* run = nullptr;
        if (it != runs.rend()) {
            run = &*it;
        } else {
            MethodRunEntry fresh;
            fresh.ex = update.ex;
            fresh.call = update.call;
            fresh.start_ms = time_ms;
            runs.push_back(std::move(fresh));
            while (runs.size() > activity_log_size_) runs.pop_front();
            run = &runs.back();
        }
        if (!update.method.empty()) run->method = update.method;
        if (update.result.empty()) {
            // A Status after the Result (delivered out of order) does not reopen the run.
            if (run->result.empty()) {
                run->status = update.status;
                if (update.progress) run->progress = update.progress;
            }
        } else {
            run->result = update.result;
            run->outcome = std::move(update.outcome);
        }
        run->time_ms = time_ms;
        run->seq = ++state_.activity_sequence;
    }
    changed_.notify_all();
}

void BridgeStore::record_event(const std::string& dev, EventLogEntry event) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        DeviceEntry* device = device_locked(dev);
        if (!device || activity_log_size_ == 0) return;
        event.seq = ++state_.activity_sequence;
        device->events.push_back(std::move(event));
        while (device->events.size() > activity_log_size_) device->events.pop_front();
    }
    changed_.notify_all();
}

bool BridgeStore::wait_for_change(std::uint64_t after_sequence, std::uint64_t after_generation, std::chrono::milliseconds timeout,
                                  std::uint64_t after_activity) const {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] {
        return state_.buffer.last_sequence() > after_sequence || state_.device_generation > after_generation ||
               state_.activity_sequence > after_activity;
    });
}

void BridgeStore::wake_all() const { changed_.notify_all(); }

}  // namespace nclink::bridge
