// Dynamic sampling (GB/T 41970-2022 8.2.17-8.2.21; docs/dynamic-sampling.md):
// an application registers a channel of data items with its own intervals
// and receives it on Sample/{dev}/{ex}/{channel} until it unregisters it or
// is gone (no DTU for the application lease, or its Notify/State offline:
// 8.2.18.3).
//
// Answers (table 19), in the order checked:
//   Register/Sample    412/102/413/405  undecodable request (DTU codec)
//                      414  no ex_cid in the topic: the channel needs an owner
//                           (its data topic and release on leave carry it)
//                      102  empty `ids`
//                      401  an id that is not a data item of the device (configs
//                           are never sampled, 6.2.2 note b)
//                      411  sampleInterval/uploadInterval not > 0, or
//                           uploadInterval < sampleInterval (attributes of the
//                           channel, table 5, that cannot work)
//                      415  max_dynamic_channels reached (all applications)
//   Unregister/Sample  412/102/413/405  undecodable request
//                      401  no channel with that id
//                      301  a model channel, or another application's channel
//                           (or no ex_cid in the topic): "Permission Denied"
//                           as 8.2.19.3/8.2.20 describe
//
// Channel ids are "dyn<n>" (n counts up per adapter run, never reused, so a
// stale Unregister cannot hit a newer channel; never a model channel's id).
//
// Threads: handle() on request workers (one mutex makes check-and-add
// atomic); on_application_gone() on the housekeeping or transport callback
// thread; stats() anywhere.
#pragma once

#include "sampling/sampling_service.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace nclink::sampling_detail {

class DynamicChannels final : public SamplingExtension {
public:
    DynamicChannels(feature_detail::FeatureHost& host, SamplingEngine& engine, const SamplingConfig& config);

    std::string_view name() const override { return "dynamic"; }
    bool handles(TopicKind kind) const override;
    void handle(const ParsedTopic& topic, const std::string& payload) override;
    void on_application_gone(const std::string& ex_cid) override;
    /// A new model: channels naming an item it no longer has are released and
    /// their owner told with an unsolicited Register/Sample/Response 401
    /// carrying the channel id (docs/wire.md).
    void on_model(const std::shared_ptr<const feature_detail::ModelState>& state) override;
    Json stats() const override;

    /// Channel ids owned by `ex_cid` (for tests and `nclink stats`).
    std::vector<std::string> channels_of(const std::string& ex_cid) const;

private:
    Json register_channel(const ParsedTopic& topic, const SampleRegisterRequest& request);
    Json unregister_channel(const ParsedTopic& topic, const SampleUnregisterRequest& request);

    feature_detail::FeatureHost& host_;
    SamplingEngine& engine_;
    const SamplingConfig& config_;  // the service's, which outlives its extensions

    mutable std::mutex mutex_;
    std::map<std::string, std::string> owners_;              // channel id -> ex_cid
    std::map<std::string, std::vector<std::string>> items_;  // channel id -> its data item ids
    std::uint64_t next_id_ = 1;
    std::uint64_t registered_ = 0, unregistered_ = 0, released_ = 0, refused_ = 0;
};

std::unique_ptr<SamplingExtension> make_dynamic_channels(feature_detail::FeatureHost& host, SamplingEngine& engine,
                                                         const SamplingConfig& config);

}  // namespace nclink::sampling_detail
