// The adapter's current model and the values the SDK holds for it: builds
// the snapshot a model file gives, installs it, and persists Probe/Set
// models and settable values. Persistence writes are atomic (temp file +
// rename), so a crash never leaves a half-written model or value file.
#pragma once

#include "driver/driver_runner.hpp"
#include "feature/model_state.hpp"

#include <nclink/driver.hpp>
#include <nclink/log.hpp>
#include <nclink/model.hpp>
#include <nclink/model_cache.hpp>
#include <nclink/values.hpp>

#include <memory>
#include <mutex>
#include <string>

namespace nclink::adapter_detail {

class ModelHost final : public feature_detail::ModelSource {
public:
    ModelHost(std::string persistence_dir, Logger logger);

    /// Builds the state for `loaded` (device `device_id`, "" = first): fills
    /// the store with fixed values and unclaimed configs, restoring persisted
    /// values of settable ones. Errors: 401 when the device is not in the model.
    /// The state is not bound yet (bind()).
    Result<std::shared_ptr<feature_detail::ModelState>> build(const LoadResult& loaded, const std::string& device_id,
                                                              const Driver& driver) const;
    /// Asks the driver for its handles (Driver::bind) for every point of
    /// `state` it is asked about: the data items of the device (and of the
    /// root configs) that the store does not hold, and the METHODs. Sets
    /// state.points; the driver's error (or 203 when busy) otherwise.
    static Result<void> bind(feature_detail::ModelState& state, driver_detail::DriverRunner& runner);

    std::shared_ptr<const feature_detail::ModelState> current() const override;
    void install(std::shared_ptr<const feature_detail::ModelState> state);

    /// Gateway mode: model files parsed once for every machine that serves
    /// them, and their value rules built once (model_cache.hpp). Before the
    /// adapter starts.
    void use_cache(std::shared_ptr<ModelCache> cache) { cache_ = std::move(cache); }
    /// load_model_file(path), through the cache when there is one.
    LoadResult load_file(const std::string& path) const { return cache_ ? cache_->load(path) : load_model_file(path); }

    /// The model file a previous Probe/Set persisted, if any ("" = none).
    std::string persisted_model_path() const;
    /// Writes the model atomically into the persistence directory.
    Result<void> persist_model(const std::string& text) const;
    /// Writes the store's settable values atomically.
    Result<void> persist_values(const ValueStore& store) const;

private:
    const std::string dir_;
    const Logger logger_;
    std::shared_ptr<ModelCache> cache_;
    mutable std::mutex mutex_;
    std::shared_ptr<const feature_detail::ModelState> current_;
};

}  // namespace nclink::adapter_detail
