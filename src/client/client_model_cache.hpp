// The client's model cache and standing registrations (8.2.5.3, 8.2.7.3,
// 8.3.6; docs/client.md, "Model cache"): the models of the devices the
// application follows, with their versions, and the event registrations and
// dynamic sample channels it made, so they can be made again when their
// adapter restarts. Pure bookkeeping under one mutex; the requests are made
// by client_model_cache.cpp.
#pragma once

#include <nclink/client.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace nclink::client_detail {

struct FollowedDevice {
    std::optional<Json> model;
    std::string version;        ///< of `model` ("" = none fetched yet)
    bool followed = false;      ///< follow_model() asked for it: re-probe on a version change
    bool watched = false;       ///< Notify/State and Probe/Version of the device are subscribed
    bool offline_seen = false;  ///< went offline since its last Probe/Version: a restart may follow
    std::string instance;       ///< the adapter run its last Probe/Version named ("" = it names none)
    Client::ModelHandler on_model;
};

struct StandingEvent {
    std::string dev;
    Client::EventRegistration registration;
    Client::EventHandler handler;
    RequestOptions options;
    std::string id;  ///< the id the adapter gave (the latest one)
};

struct StandingChannel {
    std::string dev;
    std::vector<std::string> ids;
    std::chrono::milliseconds sample_interval{0}, upload_interval{0};
    SampleHandler handler;
    RequestOptions options;
    Client::SamplingChannel channel;  ///< the latest one
};

class ModelCacheState {
public:
    std::mutex mutex;
    std::map<std::string, FollowedDevice> devices;
    std::vector<std::shared_ptr<StandingEvent>> events;
    std::vector<std::shared_ptr<StandingChannel>> channels;
    // What the application may still hold after a re-registration: the first
    // id it was given -> the record (whose id is the current one).
    std::map<std::pair<std::string, std::string>, std::shared_ptr<StandingEvent>> event_by_first_id;
    std::map<std::pair<std::string, std::string>, std::shared_ptr<StandingChannel>> channel_by_first_id;
    std::uint64_t reprobes = 0, reregistrations = 0;
};

}  // namespace nclink::client_detail
