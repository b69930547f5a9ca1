#include "events/event_engine.hpp"

#include <fmt/format.h>

namespace nclink::events_detail {

EventEngine::EventEngine(std::size_t capacity, std::string id_prefix) : capacity_(capacity), id_prefix_(std::move(id_prefix)) {}

Result<std::string> EventEngine::add(std::optional<std::string> owner, EventSpec spec) {
    if (entries_.size() >= capacity_)
        return make_error(ErrorCode::insufficient_event, fmt::format("all {} event resources are in use", capacity_));
    std::string id = fmt::format("event_{}_{}", id_prefix_, ++next_id_);
    EventWatch watch(spec.filters, spec.trigger);
    entries_.emplace(id, Entry{std::move(owner), std::move(spec), std::move(watch), false});
    return id;
}

Result<void> EventEngine::remove(const std::string& event_id, const std::optional<std::string>& owner) {
    const auto it = entries_.find(event_id);
    if (it == entries_.end())
        return make_error(ErrorCode::node_not_exists, fmt::format("no event '{}' on this adapter", event_id));
    if (it->second.owner != owner)
        return make_error(ErrorCode::permission_denied, fmt::format("event '{}' belongs to another application", event_id));
    entries_.erase(it);
    ++released_;
    return ok_result();
}

std::vector<std::string> EventEngine::remove_owner(const std::string& owner) {
    std::vector<std::string> ids;
    for (auto it = entries_.begin(); it != entries_.end();) {
        if (it->second.owner && *it->second.owner == owner) {
            ids.push_back(it->first);
            it = entries_.erase(it);
            ++released_;
        } else {
            ++it;
        }
    }
    return ids;
}

std::vector<std::string> EventEngine::retain_items(const std::function<bool(const EventSpec&)>& keep,
                                                   std::vector<std::optional<std::string>>* owners) {
    std::vector<std::string> ids;
    for (auto it = entries_.begin(); it != entries_.end();) {
        if (!keep(it->second.spec)) {
            ids.push_back(it->first);
            if (owners) owners->push_back(it->second.owner);
            it = entries_.erase(it);
            ++released_;
        } else {
            ++it;
        }
    }
    return ids;
}

void EventEngine::evaluate(const std::string& event_id, Entry& entry, const Json& whole, std::int64_t time_ms,
                           std::vector<FiredEvent>& out) {
    auto element = extract_element(entry.spec, whole);
    if (!element) return;  // the key/index is not there now: nothing to compare
    auto firing = entry.watch.observe(*element);
    if (!firing) return;
    FiredEvent fired;
    fired.owner = entry.owner;
    fired.dtu.id = event_id;
    fired.dtu.time = time_ms;
    fired.dtu.event.id = entry.spec.item;
    fired.dtu.event.value = std::move(firing->value);
    fired.dtu.event.old_value = std::move(firing->old_value);
    fired.dtu.event.key = entry.spec.key;
    if (entry.spec.index) fired.dtu.event.index = static_cast<std::int64_t>(*entry.spec.index);
    out.push_back(std::move(fired));
    ++fired_;
}

std::vector<FiredEvent> EventEngine::activate(const std::string& event_id, const std::optional<Json>& whole, std::int64_t time_ms) {
    std::vector<FiredEvent> out;
    const auto it = entries_.find(event_id);
    if (it == entries_.end() || it->second.active) return out;
    it->second.active = true;
    if (whole) evaluate(event_id, it->second, *whole, time_ms, out);
    if (it->second.watch.finished()) {
        entries_.erase(it);
        ++released_;
    }
    return out;
}

std::vector<FiredEvent> EventEngine::observe(const std::string& item, const Json& whole, std::int64_t time_ms) {
    std::vector<FiredEvent> out;
    for (auto it = entries_.begin(); it != entries_.end();) {
        Entry& entry = it->second;
        if (!entry.active || entry.spec.item != item) {
            ++it;
            continue;
        }
        evaluate(it->first, entry, whole, time_ms, out);
        if (entry.watch.finished()) {  // once: fired, released (8.2.27.4 c)
            it = entries_.erase(it);
            ++released_;
        } else {
            ++it;
        }
    }
    return out;
}

std::map<std::string, DataKind> EventEngine::active_items() const {
    std::map<std::string, DataKind> out;
    for (const auto& [id, entry] : entries_)
        if (entry.active) out.emplace(entry.spec.item, entry.spec.kind);
    return out;
}

std::set<std::string> EventEngine::watched_items() const {
    std::set<std::string> out;
    for (const auto& [id, entry] : entries_) out.insert(entry.spec.item);
    return out;
}

}  // namespace nclink::events_detail
