// The model-version cache (8.2.5-8.2.7): each adapter's announced version and
// the model fetched for it, so Probe/Query can be answered while the adapter
// is offline. Pure bookkeeping under the agent's lock.
#pragma once

#include <nclink/clock.hpp>
#include <nclink/json.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

namespace nclink::agent_detail {

struct CachedModel {
    std::string version;        ///< announced last (Probe/Version)
    std::optional<Json> model;  ///< the model fetched (Probe/Query) ...
    std::string model_version;  ///< ... for this announced version
    std::int64_t fetched_at_s = 0;
    // an outstanding fetch
    std::string fetch_id;  ///< "@id" of our Probe/Query ("" = none)
    Clock::Steady fetch_deadline{};
};

class ModelCache {
public:
    /// Records an announced version. True when the model must be fetched (none
    /// kept, or kept for another version) and no fetch is under way.
    bool announce(const std::string& dev, const std::string& version, Clock::Steady now);
    /// Marks a fetch as under way until `deadline`.
    void fetching(const std::string& dev, std::string fetch_id, Clock::Steady deadline);
    /// Stores a model (from our fetch or anyone's Probe/Query answer) for the
    /// version announced last. False when nothing changed.
    bool store(const std::string& dev, Json model, std::int64_t wall_s);
    /// Devices whose fetch is overdue (the fetch is forgotten; the next
    /// announcement or a reconnect tries again).
    void expire_fetches(Clock::Steady now);
    /// True when a fetch for `dev` is under way with `fetch_id`.
    bool is_fetch(const std::string& dev, const std::string& fetch_id) const;

    const CachedModel* find(const std::string& dev) const;
    /// A model read back from the state files (no fetch under way).
    void restore(const std::string& dev, CachedModel entry);
    const std::map<std::string, CachedModel>& all() const { return entries_; }

private:
    void forget_fetch(const std::string& dev, CachedModel& e);

    std::map<std::string, CachedModel> entries_;
    // The fetches under way by deadline: the housekeeping tick looks at the
    // overdue ones only, not at every cached model (presence.hpp).
    std::set<std::pair<Clock::Steady, std::string>> fetches_;
};

}  // namespace nclink::agent_detail
