// The features the adapter composes beside Query/Set/Probe (sampling,
// methods, events; the contract is feature/feature.hpp, which names none of
// them). The functions below are the one place of the adapter that names
// each: a new feature adds its configuration section, its factory and its
// drops there. Each feature owns its section (reading it, comparing it on
// reload) and its drop causes; these functions only list them.
//
// FeatureSet is the running features, one object: it lends them the host
// (FeatureHost), starts and stops them, and passes them what happens
// (feature.hpp says on which thread each call comes). The list is written
// once, in start() on the owner thread, before ready() turns true; it is
// only read afterwards, so it needs no lock.
#pragma once

#include "core/config_reader.hpp"
#include "feature/feature.hpp"
#include "feature/feature_metrics.hpp"

#include <nclink/adapter_config.hpp>
#include <nclink/sampling.hpp>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace nclink::adapter_detail {

/// Reads the features' sections of a configuration file (docs/configuration.md).
Result<void> read_feature_sections(core_detail::ConfigReader& top, AdapterConfig& out);

/// Appends the keys of the features' sections that differ (adapter_reload.hpp).
void feature_config_changes(const AdapterConfig& a, const AdapterConfig& b, std::vector<std::string>& out);

/// The features, in start order (stopped in reverse), each given its own section.
std::vector<std::unique_ptr<feature_detail::Feature>> make_features(feature_detail::FeatureHost& host, const AdapterConfig& config);

/// Every feature's drop causes read from a statistics snapshot's "features"
/// object (AdapterStats::features): what their add_drops() count live.
void feature_drops_from_stats(const Json& features, feature_detail::DropCounts& out);

/// Every feature's families of the adapter's exposition (docs/metrics.md),
/// written by the feature's module from a statistics snapshot's "features"
/// object and the sample channels.
void feature_metrics_from_stats(core_detail::PrometheusText& out, const core_detail::MetricLabels& device, const Json& features,
                                const SamplingStats& sampling);

/// The running features and their host.
class FeatureSet {
public:
    /// Makes the features (make_features) on `host` and starts them in
    /// order; on a failure the started ones are stopped again and the
    /// error names the feature. Owner thread, once.
    Result<void> start(feature_detail::FeatureHost host, const AdapterConfig& config);
    /// Stops them in reverse order. Owner thread.
    void stop();
    /// True once every feature started: notify_value and the statistics may reach them.
    bool ready() const { return ready_.load(std::memory_order_acquire); }

    feature_detail::SampleTap& sample_tap() { return sample_tap_; }

    /// Hands a request to the feature that answers its kind; false when none does.
    bool handle(const ParsedTopic& topic, const std::string& payload);
    void on_link(LinkState link);
    void on_model(const std::shared_ptr<const feature_detail::ModelState>& state);
    void on_application_gone(const std::string& ex_cid);
    void on_value(const std::string& id, const Json& value);
    /// Each feature's statistics under its name (AdapterStats::features).
    void add_stats(Json& out) const;
    void add_drops(feature_detail::DropCounts& out) const;
    /// The feature of type T, null when it does not run (e.g. SamplingService).
    template <class T>
    T* find() const {
        if (!ready()) return nullptr;
        for (const auto& feature : features_)
            if (auto* found = dynamic_cast<T*>(feature.get())) return found;
        return nullptr;
    }

private:
    feature_detail::SampleTap sample_tap_;
    std::unique_ptr<feature_detail::FeatureHost> host_;
    std::vector<std::unique_ptr<feature_detail::Feature>> features_;
    std::atomic<bool> ready_{false};
};

}  // namespace nclink::adapter_detail
