// ValueStore: SDK-held values behind a reader/writer lock.
#include <nclink/value_store.hpp>
#include <nclink/values.hpp>

#include "values/value_internal.hpp"

#include <mutex>

namespace nclink {

using values_detail::fail;
using values_detail::fits_kind;

namespace {

Error unknown(std::string_view id) { return fail(ErrorCode::node_not_exists, "no item \"{}\"", id); }

Result<void> check_fits(std::string_view id, const Json& value, DataKind kind) {
    if (!fits_kind(value, kind))
        return fail(ErrorCode::value_type, "item \"{}\" is a {}, its value cannot be a {}", id, to_string(kind),
                    json_type_name(value));
    return ok_result();
}

}  // namespace

Result<void> ValueStore::add(std::string id, DataKind kind, bool setable, Json initial) {
    if (auto ok = check_fits(id, initial, kind); !ok) return std::move(ok).error();
    std::unique_lock lock(mutex_);
    if (items_.count(id) != 0) return fail(ErrorCode::key_error, "item \"{}\" is already registered", id);
    items_.emplace(std::move(id), Item{kind, setable, std::move(initial)});
    return ok_result();
}

bool ValueStore::contains(std::string_view id) const {
    std::shared_lock lock(mutex_);
    return items_.find(id) != items_.end();
}

std::size_t ValueStore::size() const {
    std::shared_lock lock(mutex_);
    return items_.size();
}

std::vector<std::string> ValueStore::ids() const {
    std::shared_lock lock(mutex_);
    std::vector<std::string> out;
    out.reserve(items_.size());
    for (const auto& entry : items_) out.push_back(entry.first);
    return out;
}

Result<Json> ValueStore::query(std::string_view id, const Json& params) const {
    std::shared_lock lock(mutex_);
    const auto found = items_.find(id);
    if (found == items_.end()) return unknown(id);
    return evaluate_query(params, found->second.value, found->second.kind);
}

Result<void> ValueStore::set(std::string_view id, const Json& params) {
    std::unique_lock lock(mutex_);
    const auto found = items_.find(id);
    if (found == items_.end()) return unknown(id);
    Item& item = found->second;
    return apply_set(params, item.value, item.kind, item.setable);
}

Result<Json> ValueStore::get(std::string_view id) const {
    std::shared_lock lock(mutex_);
    const auto found = items_.find(id);
    if (found == items_.end()) return unknown(id);
    return found->second.value;
}

Result<void> ValueStore::put(std::string_view id, Json value) {
    std::unique_lock lock(mutex_);
    const auto found = items_.find(id);
    if (found == items_.end()) return unknown(id);
    if (auto ok = check_fits(id, value, found->second.kind); !ok) return std::move(ok).error();
    found->second.value = std::move(value);
    return ok_result();
}

Json ValueStore::snapshot() const {
    std::shared_lock lock(mutex_);
    Json out = Json::object();
    for (const auto& [id, item] : items_) out[id] = item.value;
    return out;
}

Result<std::size_t> ValueStore::load(const Json& snapshot) {
    if (!snapshot.is_object())
        return fail(ErrorCode::syntax_error, "a snapshot must be a JSON object, got {}", json_type_name(snapshot));
    std::unique_lock lock(mutex_);
    std::vector<std::pair<Item*, const Json*>> restores;
    for (const auto& [id, value] : snapshot.items()) {
        const auto found = items_.find(id);
        if (found == items_.end()) continue;
        if (auto ok = check_fits(id, value, found->second.kind); !ok) return std::move(ok).error();
        restores.emplace_back(&found->second, &value);
    }
    for (auto& [item, value] : restores) item->value = *value;
    return restores.size();
}

}  // namespace nclink
