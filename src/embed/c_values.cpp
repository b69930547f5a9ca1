// nclink.h: push-mode channels (rows from the firmware's real-time thread)
// and value notifications (events).
#include "embed/c_boundary.hpp"
#include "embed/c_handles.hpp"

#include <cmath>
#include <string>
#include <string_view>
#include <utility>

namespace nclink::embed {
namespace {

/// The SampleValue of a C value; false for an unknown kind. Never allocates.
bool to_sample(const nclink_value& v, SampleValue& out) noexcept {
    switch (v.kind) {
        case NCLINK_VALUE_NULL: out = SampleValue::null(); return true;
        case NCLINK_VALUE_BOOL: out = SampleValue::boolean(v.as.boolean != 0); return true;
        case NCLINK_VALUE_INT64: out = SampleValue::int64(v.as.int64); return true;
        case NCLINK_VALUE_UINT64: out = SampleValue::uint64(v.as.uint64); return true;
        case NCLINK_VALUE_FLOAT64: out = SampleValue::float64(v.as.float64); return true;
        case NCLINK_VALUE_TEXT:
        case NCLINK_VALUE_JSON: {
            if (v.as.text == nullptr && v.length > 0) return false;
            const std::string_view text(v.as.text ? v.as.text : "", v.length);
            out = v.kind == NCLINK_VALUE_TEXT ? SampleValue::text(text) : SampleValue::json(text);
            return true;
        }
        default: return false;
    }
}

/// The Json of a C value (a notification), or an error.
Result<Json> to_json(const nclink_value& v) {
    switch (v.kind) {
        case NCLINK_VALUE_NULL: return Json(nullptr);
        case NCLINK_VALUE_BOOL: return Json(v.as.boolean != 0);
        case NCLINK_VALUE_INT64: return Json(v.as.int64);
        case NCLINK_VALUE_UINT64: return Json(v.as.uint64);
        case NCLINK_VALUE_FLOAT64: return std::isfinite(v.as.float64) ? Json(v.as.float64) : Json(nullptr);
        case NCLINK_VALUE_TEXT:
        case NCLINK_VALUE_JSON: {
            if (v.as.text == nullptr && v.length > 0)
                return make_error(ErrorCode::parameter_missing, "value.as.text is NULL with a length");
            const std::string_view text(v.as.text ? v.as.text : "", v.length);
            if (v.kind == NCLINK_VALUE_TEXT) return Json(std::string(text));
            Json parsed = Json::parse(text.begin(), text.end(), nullptr, false);
            if (parsed.is_discarded()) return make_error(ErrorCode::syntax_error, "value is not JSON text");
            return parsed;
        }
        default: return make_error(ErrorCode::value_type, "value.kind " + std::to_string(v.kind) + " is no NCLINK_VALUE_*");
    }
}

int notify(nclink_adapter* adapter, const char* id, Result<Json> value) {
    if (!value) return to_int(value.error().code);
    adapter->adapter->notify_value(id, std::move(value).value());
    return 0;
}

}  // namespace
}  // namespace nclink::embed

using nclink::ErrorCode;
using nclink::to_int;
using nclink::embed::guarded;
using nclink::embed::report;

extern "C" {

int nclink_adapter_push_channel(nclink_adapter* adapter, const char* channel_id, nclink_channel** channel, nclink_error* error) {
    return guarded(error, [&] {
        if (channel == nullptr) return report(error, to_int(ErrorCode::parameter_missing), "channel (the out pointer) is NULL");
        *channel = nullptr;
        if (adapter == nullptr) return report(error, to_int(ErrorCode::parameter_missing), "adapter is NULL");
        if (channel_id == nullptr) return report(error, to_int(ErrorCode::parameter_missing), "channel_id is NULL");
        auto taken = adapter->adapter->push_channel(channel_id);
        if (!taken) return report(error, taken.error());
        auto handle = std::make_unique<nclink_channel>();
        handle->row.resize(taken->points());
        handle->channel = std::move(taken).value();
        // After a model change, take the replanned channel for the pusher.
        // The listener lives as long as the adapter; the handle may go first.
        std::weak_ptr<nclink_channel::Handoff> weak = handle->handoff;
        nclink::Adapter* owner = adapter->adapter.get();
        adapter->adapter->add_model_listener([weak, owner, id = std::string(channel_id)](std::shared_ptr<const nclink::Model>) {
            auto handoff = weak.lock();
            if (!handoff) return;
            auto next = owner->push_channel(id);
            if (!next) return;  // the new model has no such push channel: pushes are refused
            std::lock_guard<std::mutex> lock(handoff->mutex);
            handoff->row.assign(next->points(), nclink::SampleValue());
            handoff->channel = std::move(next).value();
            handoff->ready.store(true, std::memory_order_release);
        });
        *channel = handle.release();
        return nclink::embed::report_ok(error);
    });
}

size_t nclink_channel_points(const nclink_channel* channel) { return channel ? channel->row.size() : 0; }

int nclink_channel_push(nclink_channel* channel, const nclink_value* values, size_t count, int64_t time_ns) {
    // Wait-free: no allocation, no lock (PushChannel::push is wait-free and
    // noexcept, the row was sized when the channel was taken).
    if (channel == nullptr || values == nullptr) return to_int(ErrorCode::parameter_missing);
    auto& handoff = *channel->handoff;
    if (handoff.ready.load(std::memory_order_acquire)) {
        std::unique_lock<std::mutex> lock(handoff.mutex, std::try_to_lock);
        if (lock.owns_lock()) {  // else at the next push: never wait here
            std::swap(channel->channel, handoff.channel);
            channel->row.swap(handoff.row);
            handoff.ready.store(false, std::memory_order_relaxed);
        }
    }
    if (count != channel->row.size()) return to_int(ErrorCode::unavailable);
    for (size_t i = 0; i < count; ++i)
        if (!nclink::embed::to_sample(values[i], channel->row[i])) return to_int(ErrorCode::unavailable);
    const bool queued = time_ns == 0 ? channel->channel.push(channel->row.data(), count)
                                     : channel->channel.push(channel->row.data(), count, time_ns);
    return queued ? 0 : to_int(ErrorCode::unavailable);
}

void nclink_channel_release(nclink_channel* channel) {
    (void)guarded(nullptr, [&] {
        delete channel;
        return 0;
    });
}

int nclink_adapter_notify(nclink_adapter* adapter, const char* id, const nclink_value* value) {
    return guarded(nullptr, [&] {
        if (adapter == nullptr || id == nullptr || value == nullptr) return to_int(ErrorCode::parameter_missing);
        return nclink::embed::notify(adapter, id, nclink::embed::to_json(*value));
    });
}

int nclink_adapter_notify_json(nclink_adapter* adapter, const char* id, const char* value_json) {
    return guarded(nullptr, [&] {
        if (adapter == nullptr || id == nullptr || value_json == nullptr) return to_int(ErrorCode::parameter_missing);
        nclink::Json value = nclink::Json::parse(value_json, nullptr, false);
        if (value.is_discarded()) return to_int(ErrorCode::syntax_error);
        adapter->adapter->notify_value(id, std::move(value));
        return 0;
    });
}
}  // extern "C"
