// ValueStore: the values the SDK itself holds (fixed `value`s of the model,
// settable configuration objects), answered with the operations of values.hpp.
#pragma once

#include <nclink/data_kind.hpp>
#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <cstddef>
#include <functional>
#include <map>
#include <shared_mutex>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

/// A map id -> (DataKind, setable, value). Every method is thread-safe: reads
/// share a lock, writes take it exclusively, and values leave the store only
/// as copies, so no caller ever sees a value while another thread changes it.
/// No global state: the adapter owns its store(s).
class NCLINK_API ValueStore {
public:
    ValueStore() = default;
    ValueStore(const ValueStore&) = delete;
    ValueStore& operator=(const ValueStore&) = delete;

    /// Registers an item. Errors: 410 when the id is already registered,
    /// 405 when `initial` does not fit the kind (a dict needs an object, a
    /// list an array; null means "not known yet" and fits every kind).
    Result<void> add(std::string id, DataKind kind, bool setable, Json initial);

    bool contains(std::string_view id) const;
    std::size_t size() const;
    /// Registered ids in sorted order.
    std::vector<std::string> ids() const;

    /// Query with the `params` of one Query item; the response `values` array.
    /// 401 for an unknown id, else as evaluate_query().
    Result<Json> query(std::string_view id, const Json& params) const;

    /// Set with the `params` of one Set item. 401 for an unknown id, else as
    /// apply_set() (301 when the item is not setable). All-or-nothing.
    Result<void> set(std::string_view id, const Json& params);

    /// Copy of the whole value (401 for an unknown id).
    Result<Json> get(std::string_view id) const;

    /// Replaces a value from the SDK side (ignores `setable`: the model or the
    /// driver, not a remote client, is writing). 401 / 405 as above.
    Result<void> put(std::string_view id, Json value);

    /// All values as {"id": value, ...}, for persistence.
    Json snapshot() const;

    /// Restores values from a snapshot(). All-or-nothing: 412 when `snapshot`
    /// is not an object, 405 when a value does not fit its item's kind. Ids
    /// that are not registered are skipped (the model may have changed since
    /// the snapshot was written); returns how many values were restored.
    Result<std::size_t> load(const Json& snapshot);

private:
    struct Item {
        DataKind kind = DataKind::single;
        bool setable = false;
        Json value;
    };

    mutable std::shared_mutex mutex_;
    std::map<std::string, Item, std::less<>> items_;
};

}  // namespace nclink
