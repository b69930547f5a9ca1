// The adapter's current model and the values the SDK holds for it.
// Readers take a snapshot (shared_ptr) and keep using it even if a Probe/Set
// swaps the model meanwhile. Persistence writes are atomic (temp file +
// rename), so a crash never leaves a half-written model or value file.
#pragma once

#include <nclink/driver.hpp>
#include <nclink/log.hpp>
#include <nclink/model.hpp>
#include <nclink/values.hpp>

#include <memory>
#include <mutex>
#include <string>

namespace nclink::detail {

/// What one snapshot of the adapter serves: the model, the device this
/// adapter is, and the SDK-held values.
struct ModelState {
    std::shared_ptr<const Model> model;
    const Device* device = nullptr;
    std::vector<Problem> problems;             ///< conformance problems and warnings of this model
    std::shared_ptr<ValueStore> store;         ///< SDK-held items (fixed values, unclaimed configs)
    std::shared_ptr<const std::string> probe_text;  ///< the model as sent in Probe/Query (cached)
    std::shared_ptr<const Json> probe_json;

    /// True when `id` is answered from the store rather than the driver.
    bool sdk_held(const std::string& id) const { return store && store->contains(id); }
    /// A data object of this adapter's device (or of the root configs).
    const DataObject* item(const std::string& id) const;
};

class ModelHost {
public:
    ModelHost(std::string persistence_dir, Logger logger);

    /// Builds the state for `loaded` (device `device_id`, "" = first): fills
    /// the store with fixed values and unclaimed configs, restoring persisted
    /// values of settable ones. Errors: 401 when the device is not in the model.
    Result<std::shared_ptr<const ModelState>> build(const LoadResult& loaded, const std::string& device_id,
                                                    const Driver& driver) const;

    std::shared_ptr<const ModelState> current() const;
    void install(std::shared_ptr<const ModelState> state);

    /// The model file a previous Probe/Set persisted, if any ("" = none).
    std::string persisted_model_path() const;
    /// Writes the model atomically into the persistence directory.
    Result<void> persist_model(const std::string& text) const;
    /// Writes the store's settable values atomically.
    Result<void> persist_values(const ValueStore& store) const;

private:
    const std::string dir_;
    const Logger logger_;
    mutable std::mutex mutex_;
    std::shared_ptr<const ModelState> current_;
};

/// Writes `text` to `path` atomically (write a sibling temp file, fsync, rename).
Result<void> write_file_atomically(const std::string& path, const std::string& text);

}  // namespace nclink::detail
