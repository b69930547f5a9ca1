// The adapter service "sampling": runs every SAMPLE_CHANNEL of the model
// (6.2.6, 8.2.15) on one SamplingEngine, restarts them after a Probe/Set, and
// reports statistics.
//
// Extensions (dynamic channels, offline spool) plug in like this:
// - Implement a SamplingExtension (below). Register it in
//   SamplingService::SamplingService() in sampling_service.cpp, at the line
//   marked "EXTENSIONS", e.g.
//       add_extension(make_dynamic_channels(host_, *engine_));
// - handles()/handle(): the service answers sample_register_request and
//   sample_unregister_request by forwarding them to the first extension whose
//   handles() says so (without one they get NG 202 "not supported").
// - on_model/on_link/on_application_gone/start/stop/stats are forwarded to
//   every extension (start after the engine, stop before it; stats merged
//   into the service's JSON under the extension's name()).
// - The spool: wrap_sink(f) replaces the engine's sink by f(previous sink)
//   (default sink: host.transport.publish). Call it from the extension's
//   constructor (before start()).
#pragma once

#include "feature/feature.hpp"
#include "sampling/sampling_engine.hpp"

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace nclink::sampling_detail {

class SamplingExtension {
public:
    virtual ~SamplingExtension() = default;
    virtual std::string_view name() const = 0;
    virtual bool handles(TopicKind) const { return false; }
    virtual void handle(const ParsedTopic&, const std::string&) {}
    virtual Result<void> start() { return ok_result(); }
    virtual void stop() {}
    virtual void on_model(const std::shared_ptr<const feature_detail::ModelState>&) {}
    virtual void on_link(LinkState) {}
    virtual void on_application_gone(const std::string&) {}
    virtual Json stats() const { return Json::object(); }
    virtual void add_drops(feature_detail::DropCounts& /*out*/) const {}
};

class SamplingService final : public feature_detail::Feature {
public:
    /// `config`: the "sampling" section of the configuration (this feature's own).
    SamplingService(feature_detail::FeatureHost& host, SamplingConfig config);
    ~SamplingService() override;

    std::string_view name() const override { return "sampling"; }
    bool handles(TopicKind kind) const override;
    void handle(const ParsedTopic& topic, const std::string& payload) override;
    Result<void> start() override;
    void stop() override;
    void on_model(std::shared_ptr<const feature_detail::ModelState> state) override;
    void on_link(LinkState link) override;
    void on_application_gone(const std::string& ex_cid) override;
    Json stats() const override;
    void add_drops(feature_detail::DropCounts& out) const override;

    void add_extension(std::unique_ptr<SamplingExtension> extension);
    /// Replaces the DTU sink by wrapper(previous). Before start() only.
    void wrap_sink(const std::function<DtuSink(DtuSink)>& wrapper);

    SamplingEngine& engine() { return *engine_; }
    const SamplingConfig& config() const { return config_; }
    /// Typed statistics (for Adapter::sampling_stats()).
    SamplingStats typed_stats() const;
    /// Push handle for a push-mode model channel (401 unknown, 405 not push-mode).
    Result<PushChannel> push_channel(const std::string& id) const;

private:
    void start_model_channels(const feature_detail::ModelState& state);

    feature_detail::FeatureHost& host_;
    const SamplingConfig config_;
    DtuSink sink_;  // what the engine's sink forwards to (wrappable before start)
    std::unique_ptr<SamplingEngine> engine_;
    std::vector<std::unique_ptr<SamplingExtension>> extensions_;
    std::vector<std::string> model_channels_;  // ids started from the model (on_model/start: request worker/owner)
    std::mutex mutex_;                         // model_channels_, started_
    bool started_ = false;
    std::atomic<std::uint64_t> publish_errors_{0};
};

std::unique_ptr<feature_detail::Feature> make_sampling_service(feature_detail::FeatureHost& host, const SamplingConfig& config);

/// The causes SamplingService::add_drops adds, read back from its stats()
/// JSON (a statistics snapshot's "sampling"; null when absent: all 0).
void sampling_drops_from_stats(const Json& stats, feature_detail::DropCounts& out);

/// Json view of the typed stats (also what `nclink stats` prints).
Json to_json(const SamplingStats& stats);

}  // namespace nclink::sampling_detail
