#include "agent/model_cache.hpp"

namespace nclink::agent_detail {

bool ModelCache::announce(const std::string& dev, const std::string& version, Clock::Steady now) {
    CachedModel& e = entries_[dev];
    e.version = version;
    if (e.model && e.model_version == version) return false;
    if (!e.fetch_id.empty() && now < e.fetch_deadline) return false;
    return true;
}

void ModelCache::fetching(const std::string& dev, std::string fetch_id, Clock::Steady deadline) {
    CachedModel& e = entries_[dev];
    e.fetch_id = std::move(fetch_id);
    e.fetch_deadline = deadline;
}

bool ModelCache::store(const std::string& dev, Json model, std::int64_t wall_s) {
    CachedModel& e = entries_[dev];
    e.fetch_id.clear();
    if (e.model && *e.model == model && e.model_version == e.version) return false;
    e.model = std::move(model);
    e.model_version = e.version;
    e.fetched_at_s = wall_s;
    return true;
}

void ModelCache::expire_fetches(Clock::Steady now) {
    for (auto& [dev, e] : entries_)
        if (!e.fetch_id.empty() && now >= e.fetch_deadline) e.fetch_id.clear();
}

bool ModelCache::is_fetch(const std::string& dev, const std::string& fetch_id) const {
    const auto it = entries_.find(dev);
    return it != entries_.end() && !fetch_id.empty() && it->second.fetch_id == fetch_id;
}

const CachedModel* ModelCache::find(const std::string& dev) const {
    const auto it = entries_.find(dev);
    return it == entries_.end() ? nullptr : &it->second;
}

}  // namespace nclink::agent_detail
