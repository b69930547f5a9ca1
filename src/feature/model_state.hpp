// What a feature (sampling, events, methods) and the request handlers see of
// the model: one immutable snapshot per installed model. Readers take a
// snapshot (shared_ptr) and keep using it even if a Probe/Set (8.2.9) swaps
// the model meanwhile.
#pragma once

#include "driver/point_table.hpp"

#include <nclink/model.hpp>
#include <nclink/value_rules.hpp>
#include <nclink/value_store.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::feature_detail {

/// What one snapshot of the adapter serves: the model, the device this
/// adapter is, and the SDK-held values.
struct ModelState {
    std::shared_ptr<const Model> model;
    const Device* device = nullptr;
    std::vector<Problem> problems;      ///< conformance problems and warnings of this model
    std::shared_ptr<ValueStore> store;  ///< SDK-held items (fixed values, unclaimed configs)
    /// The model as provided (the vendor's file, or the Probe/Set text), sent
    /// verbatim as `probe` in Probe/Query (8.2.8): not the normalized model.
    std::shared_ptr<const std::string> probe_text;
    /// Chapter 7's rule of every data object (value_guard.hpp checks driver values against them).
    std::shared_ptr<const ValueRules> rules;
    /// What the driver's bind() answered for this model: every data item the
    /// driver is asked about and every METHOD, with its handle (driver.hpp).
    /// Null only in tests that build a state by hand.
    std::shared_ptr<const driver_detail::PointTable> points;

    /// True when `id` is answered from the store rather than the driver.
    bool sdk_held(const std::string& id) const { return store && store->contains(id); }
    /// The driver's ref of `id` when the binding has it, else null. Never an
    /// SDK-held item (ModelHost::bind() leaves those out), so a hit also
    /// answers sdk_held() without the store's lock.
    const PointRef* bound(const std::string& id) const { return points ? points->find(id) : nullptr; }
    /// A data object of this adapter's device (or of the root configs).
    const DataObject* item(const std::string& id) const;
    /// The driver's ref of `id` with its handle; a ref without handle
    /// ({id, kind, no_handle}) when the binding does not have it.
    PointRef point(const std::string& id, DataKind kind) const;
    /// The binding's generation, to hand the runner with refs from point().
    std::uint64_t generation() const { return points ? points->generation() : driver_detail::unbound; }

    /// What a request needs of one data item, as item(), bound() and the
    /// rule's lookup give it.
    struct ItemEntry {
        const DataObject* object = nullptr;  ///< null: no data item of this device
        const PointRef* bound = nullptr;
        const ValueRule* rule = nullptr;
    };
    /// item(), bound() and rules->find() of `id` in one lookup once
    /// index_items() ran (a 100-item Query made three per item), else the
    /// three lookups.
    ItemEntry entry(const std::string& id) const;
    /// Builds entry()'s index; ModelHost::bind() calls it once the binding
    /// is in place. Not after the state is shared: entry() reads it unlocked.
    void index_items();

private:
    // By position in model->data_objects(), found through the model's own
    // (shared) id index: a map of its own per adapter was 56 bytes an item
    // in every machine of a gateway.
    std::vector<ItemEntry> entries_;
};

/// Where the current snapshot comes from (the adapter's model host).
class ModelSource {
public:
    virtual ~ModelSource() = default;
    /// The snapshot to serve now (null before the first install). Thread-safe.
    virtual std::shared_ptr<const ModelState> current() const = 0;
};

}  // namespace nclink::feature_detail
