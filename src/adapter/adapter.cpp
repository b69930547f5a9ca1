// The adapter's facade and lifecycle: load and validate the model, open the
// driver, connect, build the objects (adapter_impl.hpp lists them) and start
// the features; stop in reverse order.
#include "adapter/adapter_impl.hpp"
#include "core/shared_threads_impl.hpp"
#include "adapter/adapter_model_load.hpp"
#include "adapter/adapter_reload.hpp"
#include "adapter/request_handlers.hpp"
#include "sampling/sampling_service.hpp"
#include "transport/broker_settings.hpp"
#include "transport/mosquitto_transport.hpp"
#include "transport/mqtt_loop.hpp"

#include <nclink/driver_plugin_loader.hpp>
#include <nclink/heap.hpp>
#include <nclink/mqtt_transport.hpp>

#include <random>

namespace nclink {

using driver_detail::DriverRunner;

Result<void> Adapter::Impl::start() {
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (started) return make_error(ErrorCode::unavailable, "adapter already started");
        started = true;
    }
    // What can be checked without the machine is checked before the driver's
    // open(): a start that fails later leaves an opened driver unclosed.
    if (!transport)
        if (auto usable = check_broker_url(config.broker_url); !usable) return usable;
    auto loaded = adapter_detail::load_adapter_model(config, host, logger);
    if (!loaded) return std::move(loaded).error();

    if (!driver && !config.driver_plugin.empty()) {
        auto plugin = load_driver_plugin(config.driver_plugin, config.driver_config, logger);
        if (!plugin) return std::move(plugin).error();
        driver = std::move(plugin).value();
        logger.info("driver plugin {} {} loaded from {}", driver->info().name, driver->info().version, config.driver_plugin);
    }
    if (!driver) return make_error(ErrorCode::parameter_missing, "no driver: link one or set driver.plugin in the configuration");
    if (auto opened = driver->open(DriverContext{config.driver_config, logger}); !opened)
        return make_error(opened.error().code, "driver failed to open: " + opened.error().message);

    // Before the uploader's first DTU; process-wide (nclink/heap.hpp).
    if (config.heap_keep_bytes > 0 && !keep_freed_heap(config.heap_keep_bytes))
        logger.debug(
            "heap_keep_bytes: the allocator does not take glibc's mallopt settings (another C library, or a "
            "sanitizer's allocator); left as it is");
    driver_detail::DriverRunner::Options runner_options;
    runner_options.call_timeout = config.driver_timeout;
    if (shared_threads) runner_options.pool = &shared_threads->impl().drivers;
    runner = std::make_unique<driver_detail::DriverRunner>(driver, runner_options, logger);

    auto built = host.build(loaded.value(), config.device_id, *driver);
    if (!built) return std::move(built).error();
    if (auto bound = adapter_detail::ModelHost::bind(*built.value(), *runner); !bound)
        return make_error(bound.error().code, "driver refused the model in bind(): " + bound.error().message);
    host.install(built.value());
    dev = resolve_dev_uuid(*built.value()->device, config.dev_uuid);
    const std::string instance = fmt::format(
        "{:x}{:08x}",
        static_cast<std::uint64_t>(
            std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count()),
        std::random_device{}());
    logger.info("adapter {} serving device {} (model version {}, {} SDK-held item(s), {} driver point(s))", dev,
                built.value()->device->id, built.value()->device->version, built.value()->store->size(),
                built.value()->points->points().size());

    if (!shared_threads) background = std::make_unique<core_detail::PollHost>(kBackgroundThreads, "nclink-work");
    auto* work = shared_threads ? &shared_threads->impl().work : background.get();
    if (!transport) {
        auto options = mqtt_options();
        // The outbox's sender on the work threads (shared in gateway mode),
        // with the connection's I/O on the shared loop ("mosquitto") or on a
        // loop of its own ("paho", docs/gateway.md).
        auto made =
            shared_threads && shared_threads->impl().multiplexed_mqtt && transport_detail::mosquitto_supports(options.broker_url)
                ? transport_detail::make_mosquitto_transport(
                      std::move(options), logger, transport_detail::shared_mqtt_loop(shared_threads->impl(), logger), work)
                : transport_detail::make_own_loop_transport(std::move(options), logger, work);
        if (!made) return std::move(made).error();
        transport = std::move(made).value();
    }
    transport = transport_detail::count_dtus(std::move(transport), dtus);  // DTUs by kind (docs/metrics.md)

    // The objects, each on what it needs (adapter_impl.hpp).
    auto* shared = shared_threads ? &shared_threads->impl() : nullptr;
    link = std::make_unique<adapter_detail::AdapterLink>(config, *transport, host, clock, logger, dev, instance, [this] {
        if (housekeeping) housekeeping->wake();
    });
    applications = std::make_unique<adapter_detail::ApplicationWatch>(
        *transport, dev, config.application_lease, logger, [this](const std::string& ex) { features.on_application_gone(ex); });
    model_change = std::make_unique<adapter_detail::ModelChange>(config, logger, dev, host, *driver, *runner, *link, features,
                                                                 listeners, [this] { return running(); });
    requests = std::make_unique<adapter_detail::RequestIntake>(adapter_detail::RequestIntake::Parts{
        config, logger, dev, clock, *driver, *runner, host, value_guard, *link, features, *applications, *model_change,
        [this] { return to_json(self->stats()); }, shared, background.get()});
    housekeeping = std::make_unique<adapter_detail::Housekeeping>(
        *link, *applications,
        [this](feature_detail::DropCounts& drops) {
            if (!features.ready()) return false;
            add_drops_now(drops);
            return true;
        },
        clock, logger, shared ? &shared->timers : background.get(),
        shared ? adapter_detail::kSharedHousekeepingPeriod : adapter_detail::kHousekeepingPeriod);
    composed.store(true, std::memory_order_release);

    transport->set_message_handler([this](const Message& m) { on_message(m); });
    transport->set_state_handler([this](LinkState s, std::string_view) { on_link(s); });
    auto subscriptions = topics::adapter_subscriptions(dev);
    // Applications going offline (8.2.18.3): each application's Notify/State
    // is subscribed when it first sends a DTU (adapter_applications.cpp), not
    // Notify/State/+: that would bring every terminal's retained state to
    // every adapter, N x N messages when a plant of N terminals (re)connects.
    if (auto subscribed = transport->subscribe(subscriptions, 1); !subscribed) return subscribed;
    // The features beside Query/Set/Probe (adapter_features.cpp lists them).
    if (auto begun = features.start(
            feature_detail::FeatureHost{dev, logger, clock, *transport, *runner, host, features.sample_tap(), *value_guard,
                                        [this](const ParsedTopic& topic, const Json& reply) { link->respond(topic, reply); },
                                        [this] { return link->next_msg_id(); }, config.persistence_dir, config.driver_timeout,
                                        shared ? &shared->timers : nullptr, shared ? shared->next_sampling_phase() : 0.0, work},
            config);
        !begun)
        return begun;
    link->fire(AdapterEvent::initialized);
    link->fire(
        AdapterEvent::link_lost);  // not connected yet (logged at debug: initial -> disconnected): requests' answers wait for the link
    housekeeping->start();
    return transport->start();
}

MqttOptions Adapter::Impl::mqtt_options() const {
    MqttOptions o;
    transport_detail::BrokerSettings::of(config).apply_to(o);
    if (o.client_id.empty()) o.client_id = "nclink-adapter-" + dev;
    o.outbox.max_bytes = config.offline_buffer_bytes;
    o.outbox.max_in_flight = config.max_in_flight;
    o.last_will = adapter_detail::state_message(dev, "offline");
    return o;
}

bool Adapter::Impl::running() {
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (!started || stopped) return false;
    }
    return composed.load(std::memory_order_acquire) && link->state() != AdapterState::initial;
}

// Thread: transport callback. Routes; never blocks.
void Adapter::Impl::on_message(const Message& message) {
    const auto parsed = parse_topic(message.topic);
    if (!parsed) return;
    if (parsed->kind == TopicKind::register_response) {
        link->on_register_response(message.payload);
        return;
    }
    if (parsed->kind == TopicKind::notify_state) {
        // A retained state comes from subscribing, not from a change: the
        // one stored before this application's current run may say offline.
        if (!message.retained) applications->on_notify_state(*parsed, message.payload);
        return;
    }
    requests->on_request(*parsed, message);
}

// Thread: transport callback/supervisor thread. Never blocks.
void Adapter::Impl::on_link(LinkState state) {
    link->on_link(state);
    features.on_link(state);
}

void Adapter::Impl::stop(std::chrono::milliseconds flush_timeout) {
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (!started || stopped) return;
        stopped = true;
    }
    if (link) link->stopping();
    if (housekeeping) housekeeping->stop();
    if (requests) requests->close();  // answers what is queued
    features.stop();
    if (transport) {
        (void)transport->publish(adapter_detail::state_message(dev, "offline"));  // a clean stop sends no last will
        transport->stop(flush_timeout);
    }
    // A driver call gets its usual deadline to finish; one stuck longer
    // is abandoned rather than holding up the shutdown.
    if (background) background->stop();  // every pollable was removed above
    if (runner) runner->stop(std::max(config.driver_timeout, std::chrono::milliseconds(100)));
    // A driver-affine task still inside a stuck driver must not answer
    // through a destroyed adapter when it comes back.
    if (requests) requests->release_driver_tasks();
    logger.info("adapter {} stopped", dev);
}

Adapter::Adapter(AdapterConfig config, std::shared_ptr<Driver> driver, Logger logger)
    : impl_(std::make_unique<Impl>(std::move(config), std::move(driver), std::move(logger))) {
    impl_->self = this;
}

Adapter::~Adapter() { stop(std::chrono::milliseconds(500)); }

void Adapter::use_transport(std::unique_ptr<Transport> transport) { impl_->transport = std::move(transport); }
void Adapter::use_clock(std::shared_ptr<const Clock> clock) { impl_->clock = std::move(clock); }
void Adapter::use_shared_threads(std::shared_ptr<SharedThreads> threads) { impl_->shared_threads = std::move(threads); }
void Adapter::use_model_cache(std::shared_ptr<ModelCache> cache) { impl_->host.use_cache(std::move(cache)); }
Result<void> Adapter::start() { return impl_->start(); }
void Adapter::stop(std::chrono::milliseconds flush_timeout) { impl_->stop(flush_timeout); }
std::string Adapter::dev_uuid() const { return impl_->dev; }

ConfigReload Adapter::reload(const AdapterConfig& next) {
    ConfigReload report;
    std::lock_guard<std::mutex> lock(impl_->reload_mutex);
    // Compared with the configuration the adapter runs on, so a key waiting
    // for a restart is reported at every reload until then.
    for (auto& key : adapter_detail::adapter_config_changes(impl_->config, next))
        if (key != "log_level") report.restart_needed.push_back(std::move(key));
    if (next.log_level != impl_->reloaded_level) {
        impl_->logger.set_min_level(next.log_level);
        impl_->reloaded_level = next.log_level;
        report.applied.emplace_back("log_level");
    }
    return report;
}

std::shared_ptr<const Model> Adapter::model() const {
    auto current = impl_->host.current();
    return current ? current->model : nullptr;
}

std::vector<Problem> Adapter::model_problems() const {
    auto current = impl_->host.current();
    return current ? current->problems : std::vector<Problem>{};
}

AdapterState Adapter::state() const {
    return impl_->composed.load(std::memory_order_acquire) ? impl_->link->state() : AdapterState::initial;
}

void Adapter::notify_value(const std::string& id, Json value) {
    if (!impl_->features.ready()) return;
    // Chapter 7: a pushed value breaking its item's rule reaches no event.
    if (const auto state = impl_->host.current(); state && !impl_->value_guard->admit(*state, id, value, "notify_value")) return;
    impl_->features.on_value(id, value);
}

Result<PushChannel> Adapter::push_channel(const std::string& channel_id) const {
    auto* sampling = impl_->features.find<sampling_detail::SamplingService>();
    if (!sampling || !impl_->config.sampling.enabled)
        return make_error(ErrorCode::unavailable, "sampling is not running (adapter not started, or sampling.enabled is false)");
    return sampling->push_channel(channel_id);
}

SamplingStats Adapter::sampling_stats() const {
    auto* sampling = impl_->features.find<sampling_detail::SamplingService>();
    return sampling ? sampling->typed_stats() : SamplingStats{};
}

void Adapter::add_model_listener(ModelListener listener) { impl_->listeners.add(std::move(listener)); }

Result<std::string> Adapter::replace_model(const std::string& model_json) {
    if (!impl_->composed.load(std::memory_order_acquire)) return make_error(ErrorCode::unavailable, "the adapter is not running");
    return impl_->model_change->adopt(model_json, "Adapter::replace_model");
}

Result<std::string> Adapter::patch_model(const Json& patch) {
    if (!patch.is_array()) return make_error(ErrorCode::value_type, "a JSON Patch is an array of operations");
    const auto current = impl_->host.current();
    if (!current || !impl_->composed.load(std::memory_order_acquire))
        return make_error(ErrorCode::unavailable, "the adapter is not running");
    Json patched;
    try {
        patched = Json::parse(*current->probe_text).patch(patch);
    } catch (const std::exception& e) {
        return make_error(ErrorCode::keys_of_arguments, std::string("the patch does not apply: ") + e.what());
    }
    return impl_->model_change->adopt(patched.dump(), "Adapter::patch_model");
}

}  // namespace nclink
