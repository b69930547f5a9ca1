// The registrations of one adapter and their evaluation, without threads or
// I/O: the events service (events_service.cpp) feeds it values from the
// sample stream, polls and driver pushes, and publishes what it returns.
// Unit tests drive it directly.
//
// Life of a registration: add() reserves it (416 when full) and gives the
// event id; activate() starts it with the current value (evaluated at once:
// 8.2.27.4 fires when it already matches); observe() evaluates later values;
// remove()/remove_owner()/a once trigger/retain_items() release it. Values
// observed between add() and activate() are not seen by it, so the first
// value it evaluates is always the one read at registration.
//
// Not thread-safe: the service guards it with one mutex.
#pragma once

#include "events/event_registration.hpp"
#include "events/event_watch.hpp"

#include <nclink/dtu.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace nclink::events_detail {

/// An event to publish: to `owner` (Event/{dev}/{owner}; Event/{dev} when the
/// registration came without a terminal id). msg_id and guid are left empty.
struct FiredEvent {
    std::optional<std::string> owner;
    EventData dtu;
};

class EventEngine {
public:
    /// `capacity`: EventsConfig::max_events; `id_prefix` makes the adapter's
    /// event ids unique across restarts ("event_<prefix>_<n>").
    EventEngine(std::size_t capacity, std::string id_prefix);

    /// Reserves a registration. 416 when `capacity` registrations exist.
    Result<std::string> add(std::optional<std::string> owner, EventSpec spec);
    /// Unregister/Event: 401 for an unknown id, 301 when another application
    /// (or none) registered it.
    Result<void> remove(const std::string& event_id, const std::optional<std::string>& owner);
    /// Releases every registration of `owner`; returns their ids.
    std::vector<std::string> remove_owner(const std::string& owner);
    /// Releases the registrations whose item `keep` no longer accepts (a new
    /// model without the item, or with another datatype); returns their ids.
    /// `owners`, when given, receives the owner of each, in the same order.
    std::vector<std::string> retain_items(const std::function<bool(const EventSpec&)>& keep,
                                          std::vector<std::optional<std::string>>* owners = nullptr);

    /// Starts a registration with the item's whole value at registration
    /// (std::nullopt when it could not be read: the first value observed
    /// later is then its first). Unknown ids (already removed) are ignored.
    std::vector<FiredEvent> activate(const std::string& event_id, const std::optional<Json>& whole, std::int64_t time_ms);
    /// A whole value of `item` (from a sample row, a poll or a driver push).
    std::vector<FiredEvent> observe(const std::string& item, const Json& whole, std::int64_t time_ms);

    /// Items watched by active registrations (what to poll), with their kind.
    std::map<std::string, DataKind> active_items() const;
    /// Items watched by any registration (what to pick from the sample stream).
    std::set<std::string> watched_items() const;

    std::size_t size() const noexcept { return entries_.size(); }

    bool contains(const std::string& event_id) const { return entries_.count(event_id) != 0; }
    std::uint64_t fired() const noexcept { return fired_; }
    /// Released by unregister, owner gone, model change or a once trigger.
    std::uint64_t released() const noexcept { return released_; }

private:
    struct Entry {
        std::optional<std::string> owner;
        EventSpec spec;
        EventWatch watch;
        bool active = false;
    };

    void evaluate(const std::string& event_id, Entry& entry, const Json& whole, std::int64_t time_ms, std::vector<FiredEvent>& out);

    const std::size_t capacity_;
    const std::string id_prefix_;
    std::uint64_t next_id_ = 0;
    std::map<std::string, Entry> entries_;
    std::uint64_t fired_ = 0;
    std::uint64_t released_ = 0;
};

}  // namespace nclink::events_detail
