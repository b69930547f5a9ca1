// The adapter's facade and lifecycle: load and validate the model, open the
// driver, connect, start the features; stop in reverse order. The link,
// request intake, Probe/Set and statistics live beside this file
// (adapter_impl.hpp lists them).
#include "adapter/adapter_impl.hpp"
#include "core/thread_name.hpp"
#include "core/shared_threads_impl.hpp"
#include "adapter/adapter_reload.hpp"
#include "adapter/request_handlers.hpp"
#include "adapter/adapter_features.hpp"
#include "sampling/sampling_service.hpp"
#include "transport/mosquitto_transport.hpp"
#include "transport/mqtt_loop.hpp"

#include <nclink/driver_plugin_loader.hpp>
#include <nclink/heap.hpp>
#include <nclink/mqtt_transport.hpp>

#include <nclink/model_version.hpp>

#include <filesystem>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>

namespace nclink {

using detail::DriverRunner;

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
    auto loaded = load_model();
    if (!loaded) return std::move(loaded).error();

    if (!driver && !config.driver_plugin.empty()) {
        auto plugin = load_driver_plugin(config.driver_plugin, config.driver_config, logger);
        if (!plugin) return std::move(plugin).error();
        driver = std::move(plugin).value();
        logger.info("driver plugin {} {} loaded from {}", driver->info().name, driver->info().version,
                    config.driver_plugin);
    }
    if (!driver)
        return make_error(ErrorCode::parameter_missing, "no driver: link one or set driver.plugin in the configuration");
    if (auto opened = driver->open(DriverContext{config.driver_config, logger}); !opened)
        return make_error(opened.error().code, "driver failed to open: " + opened.error().message);

    // Before the uploader's first DTU; process-wide (nclink/heap.hpp).
    if (config.heap_keep_bytes > 0 && !keep_freed_heap(config.heap_keep_bytes))
        logger.debug("heap_keep_bytes: the allocator does not take glibc's mallopt settings (another C library, or a "
                     "sanitizer's allocator); left as it is");
    DriverRunner::Options runner_options;
    runner_options.call_timeout = config.driver_timeout;
    if (shared_threads) runner_options.pool = &shared_threads->impl().drivers;
    runner = std::make_unique<DriverRunner>(driver, runner_options, logger);

    auto built = host.build(loaded.value(), config.device_id, *driver);
    if (!built) return std::move(built).error();
    if (auto bound = detail::ModelHost::bind(*built.value(), *runner); !bound)
        return make_error(bound.error().code, "driver refused the model in bind(): " + bound.error().message);
    host.install(built.value());
    dev = resolve_dev_uuid(*built.value()->device, config.dev_uuid);
    instance = fmt::format("{:x}{:08x}", static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                                                    std::chrono::system_clock::now().time_since_epoch())
                                                                    .count()),
                           std::random_device{}());
    msg_id_prefix = fmt::format("{}-{}-", dev, instance);
    logger.info("adapter {} serving device {} (model version {}, {} SDK-held item(s), {} driver point(s))", dev,
                built.value()->device->id, built.value()->device->version, built.value()->store->size(),
                built.value()->points->points().size());
    if (shared_threads) {
        auto& shared = shared_threads->impl();
        executor = std::make_unique<detail::TaskGroup>(shared.requests);
        watchdog = std::make_unique<detail::WatchdogScope>(shared.watchdog);
    } else {
        own_executor = std::make_shared<detail::Executor>(config.request_threads);
        executor = std::make_unique<detail::TaskGroup>(own_executor);
        own_watchdog = std::make_unique<detail::DeadlineWatchdog>();
        watchdog = std::make_unique<detail::WatchdogScope>(*own_watchdog);
    }
    gate = std::make_shared<detail::RequestGate>(config.max_pending_requests, config.max_request_bytes, logger);
    dedup = std::make_unique<detail::DedupWindow>(config.dedup_window, config.dedup_capacity, clock);
    applications = std::make_unique<detail::ApplicationTracker>(config.application_lease);

    if (!transport) {
        auto options = mqtt_options();
        auto made = shared_threads && shared_threads->impl().multiplexed_mqtt && detail::mosquitto_supports(options.broker_url)
                        ? detail::make_mosquitto_transport(std::move(options), logger,
                                                           detail::shared_mqtt_loop(shared_threads->impl(), logger))
                        : make_mqtt_transport(std::move(options), logger);
        if (!made) return std::move(made).error();
        transport = std::move(made).value();
    }
    transport = detail::count_dtus(std::move(transport), dtus);  // DTUs by kind (docs/metrics.md)
    transport->set_message_handler([this](const Message& m) { on_message(m); });
    transport->set_state_handler([this](LinkState s, std::string_view detail) { on_link(s, detail); });
    auto subscriptions = topics::adapter_subscriptions(dev);
    // Applications going offline (8.2.18.3): each application's Notify/State
    // is subscribed when it first sends a DTU (adapter_link.cpp), not
    // Notify/State/+: that would bring every terminal's retained state to
    // every adapter, N x N messages when a plant of N terminals (re)connects.
    if (auto subscribed = transport->subscribe(subscriptions, 1); !subscribed) return subscribed;
    if (auto made = make_features(); !made) return made;
    fire(AdapterEvent::initialized);
    fire(AdapterEvent::link_lost);  // not connected yet (logged at debug: initial -> disconnected): requests' answers wait for the link
    if (shared_threads)
        housekeeping_entry = shared_threads->impl().timers.add([this](detail::PollHost::Time now) {
            housekeep_once();
            return now + kSharedHousekeepingPeriod;
        });
    else
        housekeeping = std::thread([this] {
            detail::name_this_thread("nclink-house");
            housekeep();
        });
    return transport->start();
}


namespace {

/// The first device's version of a model file, "" when it cannot be read.
std::string device_version_of(const LoadResult& loaded, const std::string& device_id) {
    if (!loaded.model || loaded.model->devices().empty()) return {};
    const Device* device = device_id.empty() ? &loaded.model->devices().front() : loaded.model->device(device_id);
    return device ? device->version : std::string();
}

}  // namespace

// Which model to serve: the one a Probe/Set or replace_model() persisted
// (it is the current one for this device), unless the vendor ships a model
// with a newer version (a firmware update): then the shipped one wins and
// replaces the persisted file. Equal, older, or versions that cannot be
// ordered keep the persisted one. The log says which was used and why.
Result<LoadResult> Adapter::Impl::load_model() {
    std::string path = config.model_path;
    const std::string persisted = host.persisted_model_path();
    LoadResult loaded;
    bool adopt_shipped = false;
    if (!persisted.empty()) {
        LoadResult kept = load_model_file(persisted);
        LoadResult shipped = config.model_path.empty() ? LoadResult{} : load_model_file(config.model_path);
        const std::string kept_version = device_version_of(kept, config.device_id);
        const std::string shipped_version = device_version_of(shipped, config.device_id);
        const auto order = compare_model_versions(shipped_version, kept_version);
        if (shipped.model && (!kept.model || (order && *order > 0))) {
            logger.info("using the shipped model {} (version {}): newer than the persisted {} (version {})",
                        config.model_path, shipped_version, persisted, kept_version.empty() ? "?" : kept_version);
            loaded = std::move(shipped);
            adopt_shipped = true;
        } else {
            logger.info("using the persisted model {} (version {}) of the last model change{}", persisted,
                        kept_version,
                        shipped.model ? fmt::format("; the shipped {} has version {}", config.model_path,
                                                    shipped_version)
                                      : std::string());
            path = persisted;
            loaded = std::move(kept);
        }
    } else {
        if (path.empty()) return make_error(ErrorCode::parameter_missing, "no model file configured");
        // A file that is not there is not a model with a syntax error: say so
        // with the system's reason, once (the caller logs the error).
        if (std::FILE* f = std::fopen(path.c_str(), "rb"); !f) {
            const int why = errno;
            return make_error(ErrorCode::unavailable, fmt::format("cannot read the model file {}: {}", path, std::strerror(why)));
        } else {
            std::fclose(f);
        }
        loaded = load_model_file(path);
        logger.info("using the model {} (version {})", path, device_version_of(loaded, config.device_id));
    }
    for (const auto& p : loaded.problems) {
        // What refuses the model is part of the error the caller reports.
        if (p.severity == Severity::fatal || (config.strict && p.severity == Severity::conformance)) continue;
        const auto level = p.severity == Severity::warning ? LogLevel::debug : LogLevel::warn;
        logger.log(level, "{}:{}: {}: {}", path, p.pointer.empty() ? "/" : p.pointer, to_string(p.severity), p.message);
    }
    const std::string refused = detail::refusal_reasons(loaded, config.strict);
    if (!refused.empty() || !loaded.model)
        return make_error(ErrorCode::syntax_error,
                          fmt::format("model {} refused{}: {}", path, config.strict ? " (strict)" : "", refused));
    if (adopt_shipped) {
        // The persisted file is stale from now on: remove it so the next
        // start does not weigh it again.
        std::error_code ec;
        std::filesystem::remove(persisted, ec);
    }
    return loaded;
}


MqttOptions Adapter::Impl::mqtt_options() const {
    MqttOptions o;
    o.broker_url = config.broker_url;
    o.client_id = config.client_id.empty() ? "nclink-adapter-" + dev : config.client_id;
    o.username = config.username;
    o.password = config.password;
    o.tls = config.tls;
    o.mqtt_version = config.mqtt_version;
    o.keep_alive = config.keep_alive;
    o.clean_session = config.clean_session;
    o.outbox.max_bytes = config.offline_buffer_bytes;
    o.outbox.max_in_flight = config.max_in_flight;
    o.last_will = state_message("offline");
    return o;
}


Message Adapter::Impl::state_message(const char* state_text) const {
    NotifyState notify;
    notify.tid = dev;
    notify.state = state_text;
    return Message{topics::notify_state(dev), encode(notify), 1, true};
}


// The features beside Query/Set/Probe (adapter_features.cpp lists them).
Result<void> Adapter::Impl::make_features() {
    feature_host = std::make_unique<detail::FeatureHost>(detail::FeatureHost{
        dev, logger, clock, *transport, *runner, host, sample_tap, *value_guard,
        [this](const ParsedTopic& topic, const Json& reply) { respond(topic, reply); },
        [this] { return next_msg_id(); },
        config.persistence_dir, config.driver_timeout,
        shared_threads ? &shared_threads->impl().timers : nullptr,
        shared_threads ? shared_threads->impl().next_sampling_phase() : 0.0});
    features = detail::make_features(*feature_host, config);  // adapter_features.cpp
    for (std::size_t i = 0; i < features.size(); ++i) {
        if (auto begun = features[i]->start(); !begun) {
            for (std::size_t j = i; j-- > 0;) features[j]->stop();
            features.clear();
            return make_error(begun.error().code,
                              fmt::format("{} failed to start: {}", features[i]->name(), begun.error().message));
        }
    }
    features_ready.store(true, std::memory_order_release);  // notify_value may reach them now
    return ok_result();
}


void Adapter::Impl::stop(std::chrono::milliseconds flush_timeout) {
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (!started || stopped) return;
        stopped = true;
    }
    {
        std::lock_guard<std::mutex> lock(housekeeping_mutex);
        housekeeping_stopping = true;
    }
    housekeeping_wake.notify_all();
    if (housekeeping.joinable()) housekeeping.join();
    if (shared_threads) shared_threads->impl().timers.remove(housekeeping_entry);
    if (watchdog) watchdog->close();
    if (own_watchdog) own_watchdog->stop();
    if (executor) executor->close();  // answers what is queued
    if (own_executor) own_executor->stop();
    for (auto it = features.rbegin(); it != features.rend(); ++it) (*it)->stop();
    if (transport) {
        (void)transport->publish(state_message("offline"));  // a clean stop sends no last will
        transport->stop(flush_timeout);
    }
    // A driver call gets its usual deadline to finish; one stuck longer
    // is abandoned rather than holding up the shutdown.
    if (runner) runner->stop(std::max(config.driver_timeout, std::chrono::milliseconds(100)));
    {
        // A driver-affine task still inside a stuck driver must not answer
        // through a destroyed adapter when it comes back.
        std::lock_guard<std::mutex> lock(lifetime->mutex);
        lifetime->alive = false;
    }
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
Result<void> Adapter::start() { return impl_->start(); }
void Adapter::stop(std::chrono::milliseconds flush_timeout) { impl_->stop(flush_timeout); }
std::string Adapter::dev_uuid() const { return impl_->dev; }

ConfigReload Adapter::reload(const AdapterConfig& next) {
    ConfigReload report;
    std::lock_guard<std::mutex> lock(impl_->reload_mutex);
    // Compared with the configuration the adapter runs on, so a key waiting
    // for a restart is reported at every reload until then.
    for (auto& key : detail::adapter_config_changes(impl_->config, next))
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
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->state;
}

void Adapter::notify_value(const std::string& id, Json value) {
    if (!impl_->features_ready.load(std::memory_order_acquire)) return;
    // Chapter 7: a pushed value breaking its item's rule reaches no event.
    if (const auto state = impl_->host.current(); state && !impl_->value_guard->admit(*state, id, value, "notify_value"))
        return;
    for (const auto& service : impl_->features) service->on_value(id, value);
}

namespace {
detail::SamplingService* sampling_service(const std::vector<std::unique_ptr<detail::Feature>>& features) {
    for (const auto& service : features)
        if (auto* sampling = dynamic_cast<detail::SamplingService*>(service.get())) return sampling;
    return nullptr;
}
}  // namespace

Result<PushChannel> Adapter::push_channel(const std::string& channel_id) const {
    auto* sampling = impl_->features_ready.load(std::memory_order_acquire) ? sampling_service(impl_->features) : nullptr;
    if (!sampling || !impl_->config.sampling.enabled)
        return make_error(ErrorCode::unavailable, "sampling is not running (adapter not started, or sampling.enabled is false)");
    return sampling->push_channel(channel_id);
}

SamplingStats Adapter::sampling_stats() const {
    auto* sampling = impl_->features_ready.load(std::memory_order_acquire) ? sampling_service(impl_->features) : nullptr;
    return sampling ? sampling->typed_stats() : SamplingStats{};
}

void Adapter::add_model_listener(ModelListener listener) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->listeners.push_back(std::move(listener));
}

}  // namespace nclink
