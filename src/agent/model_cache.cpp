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
    forget_fetch(dev, e);
    e.fetch_id = std::move(fetch_id);
    e.fetch_deadline = deadline;
    if (!e.fetch_id.empty()) fetches_.emplace(deadline, dev);
}

void ModelCache::forget_fetch(const std::string& dev, CachedModel& e) {
    if (!e.fetch_id.empty()) fetches_.erase({e.fetch_deadline, dev});
    e.fetch_id.clear();
}

void ModelCache::restore(const std::string& dev, CachedModel entry) {
    CachedModel& e = entries_[dev];
    forget_fetch(dev, e);
    e = std::move(entry);
    e.fetch_id.clear();  // a fetch of an earlier run is nobody's now
}

bool ModelCache::store(const std::string& dev, Json model, std::int64_t wall_s) {
    CachedModel& e = entries_[dev];
    forget_fetch(dev, e);
    if (e.model && *e.model == model && e.model_version == e.version) return false;
    e.model = std::move(model);
    e.model_version = e.version;
    e.fetched_at_s = wall_s;
    return true;
}

void ModelCache::expire_fetches(Clock::Steady now) {
    while (!fetches_.empty() && fetches_.begin()->first <= now) {
        entries_[fetches_.begin()->second].fetch_id.clear();
        fetches_.erase(fetches_.begin());
    }
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
