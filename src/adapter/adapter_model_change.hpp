// Model changes at run time, one object: Probe/Set (8.2.9, 8.2.10) from an
// application and Adapter::replace_model/patch_model from the firmware take
// one path: validated like a model file, bound by the driver, persisted
// atomically, swapped in, announced with Probe/Version (8.2.5.3, 8.2.9.3),
// and handed to the features and the model listeners. One change at a time
// (its own lock), so binds and installs come in one order.
//
// Threads: probe_set() on a request worker; adopt() on whichever thread
// calls Adapter::replace_model/patch_model. The features' on_model() and the
// listeners run on that thread.
#pragma once

#include "adapter/adapter_features.hpp"
#include "adapter/adapter_link.hpp"
#include "adapter/model_host.hpp"
#include "driver/driver_runner.hpp"

#include <nclink/adapter.hpp>
#include <nclink/adapter_config.hpp>
#include <nclink/dtu.hpp>
#include <nclink/log.hpp>

#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::adapter_detail {

/// The model listeners of the adapter (Adapter::add_model_listener), from
/// before start() on. Any thread; the listeners run outside the lock.
class ModelListeners {
public:
    void add(ModelListener listener) {
        std::lock_guard<std::mutex> lock(mutex_);
        listeners_.push_back(std::move(listener));
    }
    std::vector<ModelListener> snapshot() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return listeners_;
    }

private:
    mutable std::mutex mutex_;
    std::vector<ModelListener> listeners_;
};

class ModelChange {
public:
    /// Everything referenced outlives it. `running()`: the adapter serves
    /// (started, not stopping, initialized); a change is refused otherwise.
    ModelChange(const AdapterConfig& config, const Logger& logger, std::string dev, ModelHost& host, const Driver& driver,
                driver_detail::DriverRunner& runner, AdapterLink& link, FeatureSet& features, ModelListeners& listeners,
                std::function<bool()> running);

    /// Validates, persists and swaps in a whole model; returns its version.
    /// `origin` names the caller in logs.
    Result<std::string> adopt(const std::string& text, std::string_view origin);
    /// 8.2.10: the answer to a Probe/Set.
    ProbeSetResponse probe_set(const ProbeSetRequest& request);

private:
    /// Binds the model in force again (after a Probe/Set that was bound but
    /// not installed) and installs that copy.
    void rebind_current();

    const AdapterConfig& config_;
    const Logger& logger_;
    const std::string dev_;
    ModelHost& host_;
    const Driver& driver_;
    driver_detail::DriverRunner& runner_;
    AdapterLink& link_;
    FeatureSet& features_;
    ModelListeners& listeners_;
    const std::function<bool()> running_;
    std::mutex serial_;  // one model change at a time: binds and installs come in one order
};

}  // namespace nclink::adapter_detail
