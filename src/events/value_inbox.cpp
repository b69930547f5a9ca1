#include "events/value_inbox.hpp"

#include <cmath>

namespace nclink::events_detail {

std::optional<Json> sample_value_to_json(const SampleValue& value) {
    switch (value.kind()) {
        case SampleValue::Kind::null: return std::nullopt;
        case SampleValue::Kind::boolean: return Json(value.as_bool());
        case SampleValue::Kind::int64: return Json(value.as_int64());
        case SampleValue::Kind::uint64: return Json(value.as_uint64());
        case SampleValue::Kind::float64:
            if (!std::isfinite(value.as_double())) return std::nullopt;
            return Json(value.as_double());
        case SampleValue::Kind::text: return Json(std::string(value.as_text()));
        case SampleValue::Kind::json: {
            const auto text = value.as_text();
            Json parsed = Json::parse(text.begin(), text.end(), nullptr, false);
            if (parsed.is_discarded()) return std::nullopt;
            return parsed;
        }
    }
    return std::nullopt;
}

void ValueInbox::set_watched(std::set<std::string> items) {
    std::lock_guard<std::mutex> lock(mutex_);
    watched_ = std::move(items);
}

bool ValueInbox::accept_locked() {
    if (closed_) return false;
    if (values_ >= capacity_) {
        ++dropped_;
        return false;
    }
    return true;
}

void ValueInbox::push_value(const std::string& id, const Json& value, std::int64_t time_ms) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (watched_.count(id) == 0 || !accept_locked()) return;
        items_.push_back(Item{id, value, time_ms, false, {}, {}});
        ++values_;
        if (waker_) waker_();
    }
    wake_.notify_one();
}

void ValueInbox::push_row(const std::vector<std::string>& ids, const SampleValue* values, std::int64_t time_ms) {
    bool pushed = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (watched_.empty()) return;
        for (std::size_t i = 0; i < ids.size(); ++i) {
            if (watched_.count(ids[i]) == 0) continue;
            auto value = sample_value_to_json(values[i]);
            if (!value || !accept_locked()) continue;  // a missed read: nothing to evaluate
            items_.push_back(Item{ids[i], std::move(value), time_ms, false, {}, {}});
            ++values_;
            pushed = true;
        }
        if (pushed && waker_) waker_();
    }
    if (pushed) wake_.notify_one();
}

void ValueInbox::push_activation(const std::string& event_id, std::optional<Json> whole, std::int64_t time_ms,
                                 std::chrono::steady_clock::time_point at, std::shared_future<void> responded) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (closed_) return;
        items_.push_back(Item{event_id, std::move(whole), time_ms, true, at, std::move(responded)});
        if (waker_) waker_();
    }
    wake_.notify_one();
}

ValueInbox::Work ValueInbox::wait(std::optional<std::chrono::milliseconds> timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto ready = [&] { return closed_ || !items_.empty(); };
    if (timeout) wake_.wait_for(lock, *timeout, ready);
    else wake_.wait(lock, ready);
    Work work;
    work.closed = closed_;
    if (closed_) return work;
    work.items.assign(std::make_move_iterator(items_.begin()), std::make_move_iterator(items_.end()));
    items_.clear();
    values_ = 0;
    return work;
}

void ValueInbox::close() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closed_ = true;
        items_.clear();
    }
    wake_.notify_all();
}

ValueInbox::Work ValueInbox::take() {
    std::lock_guard<std::mutex> lock(mutex_);
    Work work;
    work.closed = closed_;
    if (closed_) return work;
    work.items.assign(std::make_move_iterator(items_.begin()), std::make_move_iterator(items_.end()));
    items_.clear();
    values_ = 0;
    return work;
}

std::uint64_t ValueInbox::dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
}

}  // namespace nclink::events_detail
