#include "sampling/sampling_service.hpp"

#include "sampling/dynamic_channels.hpp"
#include "sampling/spool_extension.hpp"

#include <algorithm>

namespace nclink::sampling_detail {

namespace {

std::shared_ptr<Sleeper> sleeper_for(const std::shared_ptr<const Clock>& clock) {
    // Real time sleeps in the kernel with absolute deadlines; any other clock
    // (ManualClock in adapter tests) is polled.
    if (dynamic_cast<const SystemClock*>(clock.get()) != nullptr) return std::make_shared<NanosleepSleeper>();
    return std::make_shared<PollingSleeper>(clock);
}

}  // namespace

SamplingService::SamplingService(feature_detail::FeatureHost& host, SamplingConfig config)
    : host_(host), config_(std::move(config)) {
    sink_ = [this](Message message) {
        if (auto published = host_.transport.publish(std::move(message)); !published) {
            publish_errors_.fetch_add(1, std::memory_order_relaxed);
            host_.logger.debug("sampling: publish failed: {}", published.error().describe());
        }
    };
    EngineDeps deps;
    deps.driver = &host_.driver;
    deps.model = [this] { return host_.model.current(); };
    deps.clock = host_.clock;
    deps.sleeper = sleeper_for(host_.clock);
    // Shared timer threads wait on real time: only for a real clock. A
    // single adapter (no timers) runs its uploader on its background work
    // threads, the sampler on a thread of its own.
    if (dynamic_cast<const SystemClock*>(host_.clock.get()) != nullptr) {
        deps.timers = host_.timers;
        if (!deps.timers) deps.uploader_host = host_.work;
    }
    deps.phase = host_.timer_phase;
    deps.logger = host_.logger;
    deps.config = config_;
    deps.dev = host_.dev;
    deps.sink = [this](Message message) { sink_(std::move(message)); };
    deps.tap = &host_.sample_tap;
    deps.values = &host_.values;
    engine_ = std::make_unique<SamplingEngine>(std::move(deps));
    // EXTENSIONS (dynamic sampling, spool: see sampling_service.hpp)
    add_extension(make_dynamic_channels(host_, *engine_, config_));
    add_extension(make_spool_extension(host_, *this));
}

SamplingService::~SamplingService() { stop(); }

void SamplingService::add_extension(std::unique_ptr<SamplingExtension> extension) { extensions_.push_back(std::move(extension)); }

void SamplingService::wrap_sink(const std::function<DtuSink(DtuSink)>& wrapper) { sink_ = wrapper(std::move(sink_)); }

bool SamplingService::handles(TopicKind kind) const {
    return std::any_of(extensions_.begin(), extensions_.end(), [&](const auto& e) { return e->handles(kind); });
}

void SamplingService::handle(const ParsedTopic& topic, const std::string& payload) {
    for (auto& extension : extensions_) {
        if (extension->handles(topic.kind)) {
            extension->handle(topic, payload);
            return;
        }
    }
}

Result<void> SamplingService::start() {
    if (!config_.enabled) {
        host_.logger.info("sampling disabled by configuration (sampling.enabled = false)");
        return ok_result();
    }
    const auto state = host_.model.current();
    if (state) start_model_channels(*state);
    engine_->start();
    for (std::size_t i = 0; i < extensions_.size(); ++i) {
        if (auto begun = extensions_[i]->start(); !begun) {
            for (std::size_t j = i; j-- > 0;) extensions_[j]->stop();
            engine_->stop();
            return begun;
        }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    started_ = true;
    return ok_result();
}

void SamplingService::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!started_) return;
        started_ = false;
    }
    for (auto it = extensions_.rbegin(); it != extensions_.rend(); ++it) (*it)->stop();
    engine_->stop();  // publishes what the rings hold
}

void SamplingService::start_model_channels(const feature_detail::ModelState& state) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!state.model || !state.device) return;
    const auto& config = config_;
    for (const auto& id : config.push_channels)
        if (!state.model->channel(id))
            host_.logger.warn("sampling.push_channels names {}, which is no sample channel of the model", id);
    for (const auto& entry : config.channel_qos)
        if (!state.model->channel(entry.first))
            host_.logger.warn("sampling.channel_qos names {}, which is no sample channel of the model", entry.first);
    for (const auto& channel : state.model->channels()) {
        if (channel.device_id != state.device->id) continue;
        ChannelSpec spec;
        spec.id = channel.id;
        spec.points.reserve(channel.ids.size());
        for (const auto& item_id : channel.ids) {
            const DataObject* item = state.model->data_object(item_id);
            spec.points.push_back(PointRef{item_id, item ? item->kind : DataKind::single});
        }
        spec.sample_interval_ms = channel.sample_interval_ms;
        spec.upload_interval_ms = channel.upload_interval_ms;
        spec.topic = topics::sample(host_.dev, channel.id);
        // docs/wire.md "Transport": the Sample DTU QoS, configurable per channel.
        const auto qos = config.channel_qos.find(channel.id);
        spec.qos = qos != config.channel_qos.end() ? qos->second : config.qos;
        spec.push = std::find(config.push_channels.begin(), config.push_channels.end(), channel.id) != config.push_channels.end();
        if (auto added = engine_->add_channel(spec); !added) {
            host_.logger.error("sample channel {} not started: {}", channel.id, added.error().describe());
            continue;
        }
        model_channels_.push_back(channel.id);
        host_.logger.info("sample channel {}: {} item(s) every {} ms, published every {} ms on {}{}", channel.id,
                          spec.points.size(), spec.sample_interval_ms, spec.upload_interval_ms, spec.topic,
                          spec.push ? " (push mode)" : "");
    }
}

void SamplingService::on_model(std::shared_ptr<const feature_detail::ModelState> state) {
    engine_->set_model(state);
    if (config_.enabled && state) {
        std::vector<std::string> old;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            old.swap(model_channels_);
        }
        // The old channels' rows sampled so far are still published.
        for (const auto& id : old) engine_->remove_channel(id);
        start_model_channels(*state);
    }
    for (auto& extension : extensions_) extension->on_model(state);
}

void SamplingService::on_link(LinkState link) {
    for (auto& extension : extensions_) extension->on_link(link);
}

void SamplingService::on_application_gone(const std::string& ex_cid) {
    for (auto& extension : extensions_) extension->on_application_gone(ex_cid);
}

SamplingStats SamplingService::typed_stats() const {
    SamplingStats s;
    s.running = engine_->running();
    s.realtime = engine_->realtime();
    s.channels = engine_->stats();
    return s;
}

Result<PushChannel> SamplingService::push_channel(const std::string& id) const { return engine_->push_channel(id); }

Json SamplingService::stats() const {
    Json out = to_json(typed_stats());
    out["enabled"] = config_.enabled;
    out["publish_errors"] = publish_errors_.load(std::memory_order_relaxed);
    for (const auto& extension : extensions_) out[std::string(extension->name())] = extension->stats();
    return out;
}

namespace {
// The causes of the statistics' "drops" (docs/delivery.md, "Counted drops").
constexpr std::string_view kRingFull = "sample_ring_full";
constexpr std::string_view kPublishRefused = "sample_publish_refused";
constexpr std::string_view kSpoolFull = "sample_spool_full";

std::uint64_t count_at(const Json& object, std::initializer_list<const char*> path) {
    const Json* at = &object;
    for (const char* key : path) {
        if (!at->is_object()) return 0;
        const auto it = at->find(key);
        if (it == at->end()) return 0;
        at = &*it;
    }
    return at->is_number_unsigned() || at->is_number_integer() ? at->get<std::uint64_t>() : 0;
}
}  // namespace

void SamplingService::add_drops(feature_detail::DropCounts& out) const {
    out.add(kRingFull, engine_->ring_drops());
    out.add(kSpoolFull, 0);  // the spool extension adds its own
    out.add(kPublishRefused, publish_errors_.load(std::memory_order_relaxed));
    for (const auto& extension : extensions_) extension->add_drops(out);
}

void sampling_drops_from_stats(const Json& stats, feature_detail::DropCounts& out) {
    std::uint64_t ring_full = 0;
    if (stats.is_object())
        if (const auto channels = stats.find("channels"); channels != stats.end() && channels->is_array())
            for (const auto& c : *channels) ring_full += count_at(c, {"drops"});
    out.add(kRingFull, ring_full);
    out.add(kSpoolFull, count_at(stats, {"spool", "dropped"}));
    out.add(kPublishRefused, count_at(stats, {"publish_errors"}));
}

Json to_json(const SamplingStats& stats) {
    Json channels = Json::array();
    for (const auto& c : stats.channels) {
        Json lateness = Json::object();
        for (std::size_t i = 0; i < c.lateness.size(); ++i) {
            const std::string key = i < kLatenessBoundsUs.size() ? "lt_" + std::to_string(kLatenessBoundsUs[i])
                                                                 : "ge_" + std::to_string(kLatenessBoundsUs.back());
            lateness[key] = c.lateness[i];
        }
        Json entry = {{"id", c.id},
                      {"topic", c.topic},
                      {"push", c.push},
                      {"sample_interval_ms", c.sample_interval_ms},
                      {"upload_interval_ms", c.upload_interval_ms},
                      {"points", c.points},
                      {"ring_capacity", c.ring_capacity},
                      {"rows_sampled", c.rows_sampled},
                      {"rows_published", c.rows_published},
                      {"dtus_published", c.dtus_published},
                      {"overruns", c.overruns},
                      {"skipped_ticks", c.skipped_ticks},
                      {"drops", c.drops},
                      {"null_values", c.null_values},
                      {"refused_values", c.refused_values},
                      {"max_lateness_us", c.max_lateness_us},
                      {"lateness_us", lateness}};
        if (!c.owner_ex.empty()) entry["owner_ex"] = c.owner_ex;
        channels.push_back(std::move(entry));
    }
    const auto& rt = stats.realtime;
    Json realtime = {{"fifo_priority", rt.fifo_priority},
                     {"fifo_granted", rt.fifo_granted},
                     {"timer_slack_ns", rt.timer_slack_ns},
                     {"timer_slack_granted", rt.timer_slack_granted},
                     {"cpu", rt.cpu},
                     {"cpu_granted", rt.cpu_granted},
                     {"slice_us", rt.slice_us},
                     {"slice_granted", rt.slice_granted}};
    return Json{{"running", stats.running}, {"realtime", realtime}, {"channels", channels}};
}

std::unique_ptr<feature_detail::Feature> make_sampling_service(feature_detail::FeatureHost& host, const SamplingConfig& config) {
    return std::make_unique<SamplingService>(host, config);
}

}  // namespace nclink::sampling_detail
