// Client: the model cache (8.2.5.3, 8.2.7.3) and standing registrations
// (8.3.6). Probe/Version of a followed device with a version other than the
// cached model's fetches the model again; a device that went offline and
// then announces its version again gets this client's event registrations
// and dynamic channels made again (docs/client.md, "Model cache").
//
// Threads: the public calls on any thread; the Notify/State and
// Probe/Version handlers, and every completion, on the dispatch thread,
// which may make async requests (the client's thread contract).
#include "client/client_impl.hpp"

#include <algorithm>
#include <cctype>

namespace nclink {

using client_detail::StandingChannel;
using client_detail::StandingEvent;

namespace {

// Set while the cache makes a registration again: that call neither records
// a new standing registration nor translates ids.
thread_local bool t_reregistering = false;

struct Reregistering {
    Reregistering() : outer(t_reregistering) { t_reregistering = true; }
    ~Reregistering() { t_reregistering = outer; }
    const bool outer;  // a completion may run inside the loop that set it
};

bool is_once(const std::string& trigger) {
    std::string t = trigger;
    for (auto& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return t == "once";  // released by the adapter after its first event: nothing stands
}

}  // namespace

Result<void> Client::Impl::watch_device(const std::string& dev) {
    {
        std::lock_guard<std::mutex> lock(model_cache.mutex);
        auto& d = model_cache.devices[dev];
        if (d.watched) return ok_result();
        d.watched = true;
    }
    auto state =
        link.subscribe(topics::notify_state(dev), StateHandler([this, dev](const NotifyState& n) { on_device_state(dev, n); }));
    auto version = link.subscribe(topics::probe_version(dev),
                                  VersionHandler([this, dev](const ProbeVersionRequest& v) { on_device_version(dev, v); }));
    if (!state || !version) {
        std::lock_guard<std::mutex> lock(model_cache.mutex);
        model_cache.devices[dev].watched = false;
        return make_error(ErrorCode::unavailable, "cannot subscribe to the device's state and version");
    }
    return ok_result();
}

void Client::Impl::on_device_state(const std::string& dev, const NotifyState& state) {
    if (state.state != "offline") return;
    std::lock_guard<std::mutex> lock(model_cache.mutex);
    model_cache.devices[dev].offline_seen = true;
}

namespace {
std::string instance_of(const std::optional<Json>& private_info) {
    if (!private_info || !private_info->is_object()) return {};
    const auto it = private_info->find("instance");
    return it != private_info->end() && it->is_string() ? it->get<std::string>() : std::string();
}
}  // namespace

void Client::Impl::note_instance(const std::string& dev, const std::string& payload) {
    const Json reply = Json::parse(payload, nullptr, false);
    if (!reply.is_object() || !reply.contains("privateInfo")) return;
    const std::string instance = instance_of(reply["privateInfo"]);
    if (instance.empty()) return;
    std::lock_guard<std::mutex> lock(model_cache.mutex);
    model_cache.devices[dev].instance = instance;
}

void Client::Impl::on_device_version(const std::string& dev, const ProbeVersionRequest& version) {
    bool restarted = false, changed = false;
    {
        std::lock_guard<std::mutex> lock(model_cache.mutex);
        auto& d = model_cache.devices[dev];
        // An nclink adapter names its run in privateInfo.instance: the same
        // run after an outage (a broker restart publishes its last will too)
        // still holds every registration, and registering again would drop
        // the events fired in between. Without the marker, "offline, then a
        // version" is taken as a restart.
        const std::string instance = instance_of(version.private_info);
        const bool same_run = !instance.empty() && instance == d.instance;
        restarted = d.offline_seen && !same_run;
        if (d.offline_seen && same_run) log.info("client: {} is back, the same run: its registrations stand", dev);
        d.offline_seen = false;
        if (!instance.empty()) d.instance = instance;
        changed = d.followed && version.version != d.version;
    }
    std::size_t resent = 0;
    for (auto& [id, error] : machine.resend(dev, resent)) fail_request(id, std::move(error));
    if (resent > 0) {
        counters.resent += resent;
        log.info("client: {} announced itself: {} request(s) from the reconnect queue sent again", dev, resent);
    }
    if (changed) {
        log.info("client: {} announces model version {}: fetching its model", dev, version.version);
        reprobe(dev);
    }
    if (restarted) reregister(dev);
}

void Client::Impl::reprobe(const std::string& dev) {
    owner->probe_async(dev, [this, dev](Result<Json> model) {
        if (!model) {
            log.warn("client: fetching the model of {} failed: {}", dev, model.error().describe());
            return;
        }
        std::string version;
        const Json& devices = model.value().contains("devices") ? model.value()["devices"] : Json();
        for (const auto& d : devices.is_array() ? devices : Json::array())
            if (d.is_object() && d.value("guid", "") == dev && d.contains("version") && d["version"].is_string())
                version = d["version"].get<std::string>();
        if (version.empty() && devices.is_array() && !devices.empty() && devices[0].is_object() &&
            devices[0].contains("version") && devices[0]["version"].is_string())
            version = devices[0]["version"].get<std::string>();
        Client::ModelHandler handler;
        {
            std::lock_guard<std::mutex> lock(model_cache.mutex);
            auto& d = model_cache.devices[dev];
            d.model = model.value();
            d.version = version;
            handler = d.on_model;
            ++model_cache.reprobes;
        }
        if (handler) client_detail::safely(log, [&] { handler(dev, model.value()); });
    });
}

void Client::Impl::reregister(const std::string& dev) {
    std::vector<std::shared_ptr<StandingEvent>> events;
    std::vector<std::shared_ptr<StandingChannel>> channels;
    {
        std::lock_guard<std::mutex> lock(model_cache.mutex);
        for (const auto& e : model_cache.events)
            if (e->dev == dev) events.push_back(e);
        for (const auto& c : model_cache.channels)
            if (c->dev == dev) channels.push_back(c);
    }
    if (events.empty() && channels.empty()) return;
    log.info("client: {} is back after being offline: registering {} event(s) and {} channel(s) again", dev, events.size(),
             channels.size());
    const Reregistering guard;
    // Each registration is made again only once its unregistration is
    // answered: the adapter handles requests on more than one worker, so a
    // Register sent right behind it could be handled first and then be
    // removed by the Unregister (the same id comes back from a new run).
    for (const auto& e : events) {
        // After a restart the Unregister gets 401: nothing to remove.
        owner->unregister_event_async(dev, e->id, [this, dev, e](Result<void>) {
            const Reregistering again;  // on the dispatch thread now
            owner->register_event_async(
                dev, e->registration, e->handler,
                [this, e](Result<std::string> id) {
                    std::lock_guard<std::mutex> lock(model_cache.mutex);
                    if (id) {
                        e->id = id.value();
                        ++model_cache.reregistrations;
                        return;
                    }
                    log.warn("client: event on {} at {} not registered again: {}", e->registration.id, e->dev,
                             id.error().describe());
                    auto& all = model_cache.events;
                    all.erase(std::remove(all.begin(), all.end(), e), all.end());
                },
                e->options);
        });
    }
    for (const auto& c : channels) {
        owner->unregister_sampling_async(c->channel, [this, dev, c](Result<void>) {
            const Reregistering again;  // on the dispatch thread now
            owner->register_sampling_async(
                dev, c->ids, c->sample_interval, c->upload_interval, c->handler,
                [this, c](Result<Client::SamplingChannel> channel) {
                    std::lock_guard<std::mutex> lock(model_cache.mutex);
                    if (channel) {
                        c->channel = channel.value();
                        ++model_cache.reregistrations;
                        return;
                    }
                    log.warn("client: dynamic channel at {} not registered again: {}", c->dev, channel.error().describe());
                    auto& all = model_cache.channels;
                    all.erase(std::remove(all.begin(), all.end(), c), all.end());
                },
                c->options);
        });
    }
}

Completion<std::string> Client::Impl::stand_event(const std::string& dev, const Client::EventRegistration& registration,
                                                  const Client::EventHandler& handler, const RequestOptions& request_options,
                                                  Completion<std::string> done) {
    if (t_reregistering || is_once(registration.trigger)) return done;
    if (!watch_device(dev)) log.warn("client: {} cannot be watched: its events will not be registered again", dev);
    auto record = std::make_shared<StandingEvent>(StandingEvent{dev, registration, handler, request_options, {}});
    return [this, record, done = std::move(done)](Result<std::string> id) {
        if (id) {
            std::lock_guard<std::mutex> lock(model_cache.mutex);
            record->id = id.value();
            model_cache.events.push_back(record);
            model_cache.event_by_first_id[{record->dev, record->id}] = record;
        }
        if (done) done(std::move(id));
    };
}

Completion<Client::SamplingChannel> Client::Impl::stand_channel(const std::string& dev, const std::vector<std::string>& item_ids,
                                                                std::chrono::milliseconds sample_interval,
                                                                std::chrono::milliseconds upload_interval,
                                                                const SampleHandler& handler, const RequestOptions& request_options,
                                                                Completion<Client::SamplingChannel> done) {
    if (t_reregistering) return done;
    if (!watch_device(dev)) log.warn("client: {} cannot be watched: its channels will not be registered again", dev);
    auto record = std::make_shared<StandingChannel>(
        StandingChannel{dev, item_ids, sample_interval, upload_interval, handler, request_options, {}});
    return [this, record, done = std::move(done)](Result<Client::SamplingChannel> channel) {
        if (channel) {
            std::lock_guard<std::mutex> lock(model_cache.mutex);
            record->channel = channel.value();
            model_cache.channels.push_back(record);
            model_cache.channel_by_first_id[{record->dev, record->channel.id}] = record;
        }
        if (done) done(std::move(channel));
    };
}

std::string Client::Impl::unstand_event(const std::string& dev, const std::string& event_id) {
    if (t_reregistering) return event_id;
    std::lock_guard<std::mutex> lock(model_cache.mutex);
    auto it = model_cache.event_by_first_id.find({dev, event_id});
    std::shared_ptr<StandingEvent> record = it != model_cache.event_by_first_id.end() ? it->second : nullptr;
    if (!record)
        for (const auto& e : model_cache.events)
            if (e->dev == dev && e->id == event_id) record = e;
    if (!record) return event_id;
    auto& all = model_cache.events;
    all.erase(std::remove(all.begin(), all.end(), record), all.end());
    for (auto i = model_cache.event_by_first_id.begin(); i != model_cache.event_by_first_id.end();)
        i = i->second == record ? model_cache.event_by_first_id.erase(i) : std::next(i);
    return record->id;
}

Client::SamplingChannel Client::Impl::unstand_channel(const Client::SamplingChannel& channel) {
    if (t_reregistering) return channel;
    std::lock_guard<std::mutex> lock(model_cache.mutex);
    auto it = model_cache.channel_by_first_id.find({channel.dev, channel.id});
    std::shared_ptr<StandingChannel> record = it != model_cache.channel_by_first_id.end() ? it->second : nullptr;
    if (!record)
        for (const auto& c : model_cache.channels)
            if (c->dev == channel.dev && c->channel.id == channel.id) record = c;
    if (!record) return channel;
    auto& all = model_cache.channels;
    all.erase(std::remove(all.begin(), all.end(), record), all.end());
    for (auto i = model_cache.channel_by_first_id.begin(); i != model_cache.channel_by_first_id.end();)
        i = i->second == record ? model_cache.channel_by_first_id.erase(i) : std::next(i);
    return record->channel;
}

// ---- the facade

Result<void> Client::follow_model(const std::string& dev, ModelHandler on_model) {
    if (dev.empty() || dev.find_first_of("+#/") != std::string::npos)
        return make_error(ErrorCode::value_type, "follow_model: bad device id");
    {
        std::lock_guard<std::mutex> lock(impl_->model_cache.mutex);
        auto& d = impl_->model_cache.devices[dev];
        d.followed = true;
        d.on_model = std::move(on_model);
    }
    if (auto watched = impl_->watch_device(dev); !watched) return watched;
    impl_->reprobe(dev);
    return ok_result();
}

std::optional<Json> Client::cached_model(const std::string& dev) const {
    std::lock_guard<std::mutex> lock(impl_->model_cache.mutex);
    auto it = impl_->model_cache.devices.find(dev);
    return it == impl_->model_cache.devices.end() ? std::nullopt : it->second.model;
}

std::string Client::cached_model_version(const std::string& dev) const {
    std::lock_guard<std::mutex> lock(impl_->model_cache.mutex);
    auto it = impl_->model_cache.devices.find(dev);
    return it == impl_->model_cache.devices.end() ? std::string() : it->second.version;
}

std::uint64_t Client::model_reprobes() const {
    std::lock_guard<std::mutex> lock(impl_->model_cache.mutex);
    return impl_->model_cache.reprobes;
}

std::uint64_t Client::reregistrations() const {
    std::lock_guard<std::mutex> lock(impl_->model_cache.mutex);
    return impl_->model_cache.reregistrations;
}

}  // namespace nclink
