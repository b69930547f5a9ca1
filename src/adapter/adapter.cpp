#include <nclink/adapter.hpp>
#include <nclink/driver_plugin_loader.hpp>
#include <nclink/dtu.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/topics.hpp>

#include "feature/feature.hpp"
#include "adapter/adapter_reload.hpp"
#include "adapter/application_tracker.hpp"
#include "adapter/dedup_window.hpp"
#include "adapter/model_host.hpp"
#include "adapter/request_handlers.hpp"
#include "core/deadline_watchdog.hpp"
#include "core/executor.hpp"
#include "sampling/sampling_service.hpp"
#include "driver/driver_runner.hpp"
#include "methods/methods_service.hpp"
#include "events/events_service.hpp"

#include <atomic>
#include <condition_variable>
#include <map>
#include <random>
#include <thread>

namespace nclink {

using detail::DriverRunner;
using detail::ModelState;

struct Adapter::Impl {
    Impl(AdapterConfig c, std::shared_ptr<Driver> d, Logger l)
        : config(std::move(c)), logger(std::move(l)), driver(std::move(d)), host(config.persistence_dir, logger) {}

    // Lets a driver-affine task that returns from a stuck driver after the
    // adapter is gone (its worker was abandoned at stop) see that, instead of
    // touching a destroyed adapter.
    struct Lifetime {
        std::mutex mutex;
        bool alive = true;
    };
    struct Affine {
        detail::AnswerClaim* claim = nullptr;  ///< null: not a driver-affine task
        Lifetime* life = nullptr;
    };

    // ---- configuration and collaborators
    const Adapter* self = nullptr;  // the owner, for its stats() (the statistics data item)
    AdapterConfig config;  // as started: never written after construction
    Logger logger;
    std::mutex reload_mutex;
    LogLevel reloaded_level = config.log_level;  // under reload_mutex: the level the last reload set
    std::shared_ptr<Driver> driver;
    std::unique_ptr<Transport> transport;
    std::shared_ptr<const Clock> clock = std::make_shared<SystemClock>();
    detail::ModelHost host;
    std::unique_ptr<DriverRunner> runner;
    std::unique_ptr<detail::Executor> executor;
    std::unique_ptr<detail::DedupWindow> dedup;
    std::unique_ptr<detail::DeadlineWatchdog> watchdog;
    std::shared_ptr<Lifetime> lifetime = std::make_shared<Lifetime>();
    std::string dev;
    std::string msg_id_prefix;

    // ---- features (sampling, events, methods): see adapter_service.hpp
    detail::SampleTap sample_tap;
    std::unique_ptr<detail::FeatureHost> service_host;
    std::vector<std::unique_ptr<detail::Feature>> services;
    std::atomic<bool> services_ready{false};  // set once `services` is complete and started
    std::unique_ptr<detail::ApplicationTracker> applications;

    // ---- state (mutex)
    mutable std::mutex mutex;
    AdapterState state = AdapterState::initial;
    std::vector<ModelListener> listeners;
    bool started = false;
    bool stopped = false;

    // ---- registration (housekeeping thread)
    std::mutex reg_mutex;
    std::condition_variable reg_wake;
    std::thread housekeeping;
    bool reg_stopping = false;
    bool reg_pending = false;       // a Register/Request is out, unanswered
    std::string reg_msg_id;
    Clock::Steady reg_deadline{};
    std::chrono::milliseconds reg_backoff{0};
    std::atomic<bool> registered{false};

    std::atomic<std::uint64_t> requests{0}, ignored_retained{0}, ignored_duplicates{0}, rejected{0}, msg_counter{0}, affine_timeouts{0};

    // ------------------------------------------------------------- lifecycle

    Result<void> start() {
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (started) return make_error(ErrorCode::unavailable, "adapter already started");
            started = true;
        }
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

        auto built = host.build(loaded.value(), config.device_id, *driver);
        if (!built) return std::move(built).error();
        host.install(built.value());
        dev = resolve_dev_uuid(*built.value()->device, config.dev_uuid);
        msg_id_prefix = fmt::format("{}-{:x}-", dev, std::random_device{}());
        logger.info("adapter {} serving device {} (model version {}, {} SDK-held item(s))", dev,
                    built.value()->device->id, built.value()->device->version, built.value()->store->size());

        DriverRunner::Options runner_options;
        runner_options.call_timeout = config.driver_timeout;
        runner = std::make_unique<DriverRunner>(driver, runner_options, logger);
        executor = std::make_unique<detail::Executor>(config.request_threads);
        watchdog = std::make_unique<detail::DeadlineWatchdog>();
        dedup = std::make_unique<detail::DedupWindow>(config.dedup_window, config.dedup_capacity, clock);
        applications = std::make_unique<detail::ApplicationTracker>(config.application_lease);

        if (!transport) {
            auto made = make_mqtt_transport(mqtt_options(), logger);
            if (!made) return std::move(made).error();
            transport = std::move(made).value();
        }
        transport->set_message_handler([this](const Message& m) { on_message(m); });
        transport->set_state_handler([this](LinkState s, std::string_view detail) { on_link(s, detail); });
        auto subscriptions = topics::adapter_subscriptions(dev);
        subscriptions.push_back(topics::notify_state("+"));  // applications going offline (8.2.18.3)
        if (auto subscribed = transport->subscribe(subscriptions, 1); !subscribed) return subscribed;
        if (auto made = make_services(); !made) return made;
        fire(AdapterEvent::initialized);
        fire(AdapterEvent::link_lost);  // not connected yet: requests' answers wait for the link
        housekeeping = std::thread([this] { housekeep(); });
        return transport->start();
    }

    Result<LoadResult> load_model() {
        std::string path = host.persisted_model_path();
        if (!path.empty())
            logger.info("using the model of the last Probe/Set, {}", path);
        else
            path = config.model_path;
        if (path.empty()) return make_error(ErrorCode::parameter_missing, "no model file configured");
        LoadResult loaded = load_model_file(path);
        for (const auto& p : loaded.problems) {
            const auto level = p.severity == Severity::warning ? LogLevel::debug : LogLevel::warn;
            logger.log(level, "{}:{}: {}: {}", path, p.pointer.empty() ? "/" : p.pointer, to_string(p.severity), p.message);
        }
        const std::string refused = detail::refusal_reasons(loaded, config.strict);
        if (!refused.empty() || !loaded.model)
            return make_error(ErrorCode::syntax_error,
                              fmt::format("model {} refused{}: {}", path, config.strict ? " (strict)" : "", refused));
        return loaded;
    }

    MqttOptions mqtt_options() const {
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

    Message state_message(const char* state_text) const {
        NotifyState notify;
        notify.tid = dev;
        notify.state = state_text;
        return Message{topics::notify_state(dev), encode(notify), 1, true};
    }

    // The features beside Query/Set/Probe. Each module adds its factory here.
    Result<void> make_services() {
        service_host = std::make_unique<detail::FeatureHost>(detail::FeatureHost{
            dev, logger, clock, *transport, *runner, host, sample_tap,
            [this](const ParsedTopic& topic, const Json& reply) { respond(topic, reply); },
            [this] { return next_msg_id(); },
            config.sampling, config.events, config.methods, config.persistence_dir, config.driver_timeout});
        // (factories: services.push_back(detail::make_..._service(*service_host));)
        services.push_back(detail::make_sampling_service(*service_host));
        services.push_back(detail::make_methods_service(*service_host));
        services.push_back(detail::make_events_service(*service_host));
        for (std::size_t i = 0; i < services.size(); ++i) {
            if (auto begun = services[i]->start(); !begun) {
                for (std::size_t j = i; j-- > 0;) services[j]->stop();
                services.clear();
                return make_error(begun.error().code,
                                  fmt::format("{} failed to start: {}", services[i]->name(), begun.error().message));
            }
        }
        services_ready.store(true, std::memory_order_release);  // notify_value may reach them now
        return ok_result();
    }

    void stop(std::chrono::milliseconds flush_timeout) {
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (!started || stopped) return;
            stopped = true;
        }
        {
            std::lock_guard<std::mutex> lock(reg_mutex);
            reg_stopping = true;
        }
        reg_wake.notify_all();
        if (housekeeping.joinable()) housekeeping.join();
        if (watchdog) watchdog->stop();
        if (executor) executor->stop();  // answers what is queued
        for (auto it = services.rbegin(); it != services.rend(); ++it) (*it)->stop();
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

    // ----------------------------------------------------------- the link

    // Thread: transport callback/supervisor thread. Never blocks.
    void on_link(LinkState link, std::string_view) {
        if (link == LinkState::connected) {
            (void)transport->publish(state_message("online"));
            send_registration();
            publish_version();
            fire(AdapterEvent::link_restored);
        } else if (link == LinkState::disconnected) {
            fire(AdapterEvent::link_lost);
        }
        for (auto& service : services) service->on_link(link);
    }

    void fire(AdapterEvent event) {
        std::lock_guard<std::mutex> lock(mutex);
        const auto t = adapter_transition(state, event);
        if (t.next != state) logger.info("adapter state: {} -> {} ({})", to_string(state), to_string(t.next), to_string(event));
        state = t.next;
    }

    std::string next_msg_id() { return msg_id_prefix + std::to_string(++msg_counter); }

    void send_registration() {
        RegisterRequest request;
        request.msg_id = Json(next_msg_id());
        request.cli_uuid = dev;
        {
            std::lock_guard<std::mutex> lock(reg_mutex);
            reg_pending = true;
            reg_msg_id = request.msg_id->get<std::string>();
            reg_deadline = clock->now() + config.register_timeout;
        }
        (void)transport->publish(Message{topics::register_request(), encode(request), 1, false});
        reg_wake.notify_all();
    }

    void publish_version() {
        const auto current = host.current();
        ProbeVersionRequest version;
        version.msg_id = Json(next_msg_id());
        version.guid = dev;
        version.version = current->device->version;
        (void)transport->publish(Message{topics::probe_version(dev), encode(version), 1, false});
    }

    // Thread: housekeeping. Registers again when no agent answered in time,
    // with a growing interval; the adapter serves all along (WIRE.md: proceed
    // if no agent answers). Polls the injected clock every 50 ms, so tests
    // drive it with a ManualClock.
    void housekeep() {
        std::unique_lock<std::mutex> lock(reg_mutex);
        bool retry_armed = false;
        Clock::Steady retry_at{};
        while (!reg_stopping) {
            const auto now = clock->now();
            if (reg_pending && now >= reg_deadline) {
                reg_backoff = std::min(config.register_retry_max,
                                       reg_backoff.count() == 0 ? config.register_timeout : reg_backoff * 2);
                // Said once at info; the retries that follow are routine.
                logger.log(reg_backoff == config.register_timeout ? LogLevel::info : LogLevel::debug,
                           "no Register/Response from an agent within {} ms; serving anyway, retrying in {} ms",
                           config.register_timeout.count(), reg_backoff.count());
                reg_pending = false;
                retry_armed = true;
                retry_at = now + reg_backoff;
            }
            if (retry_armed && (registered || reg_pending)) retry_armed = false;  // answered, or a reconnect re-sent it
            if (auto expired = applications->expire(now); !expired.empty()) {
                lock.unlock();
                for (const auto& ex : expired) application_gone(ex, "silent for the application lease");
                lock.lock();
                continue;
            }
            if (retry_armed && now >= retry_at) {
                retry_armed = false;
                lock.unlock();
                if (transport->state() == LinkState::connected) send_registration();
                lock.lock();
                continue;
            }
            reg_wake.wait_for(lock, std::chrono::milliseconds(50));
        }
    }

    void on_register_response(const std::string& payload) {
        auto response = decode<RegisterResponse>(payload);
        if (!response || response->cli_uuid != dev) return;
        {
            std::lock_guard<std::mutex> lock(reg_mutex);
            const bool ours = response->msg_id && response->msg_id->is_string() && response->msg_id->get<std::string>() == reg_msg_id;
            if (!ours && response->msg_id) return;  // an answer to an older request
            reg_pending = false;
            reg_backoff = std::chrono::milliseconds(0);
        }
        if (response->status.ok) {
            registered = true;
            logger.info("registered with the agent as {}", dev);
        } else {
            registered = false;
            logger.error("the agent refused registration of {}: {} {}", dev, response->status.error.value_or(0),
                         response->status.reason.value_or("(no reason)"));
        }
        reg_wake.notify_all();
    }

    void application_gone(const std::string& ex, std::string_view why) {
        logger.info("application {} is gone ({}): releasing its channels and events", ex, why);
        for (auto& service : services) service->on_application_gone(ex);
    }

    void on_notify_state(const ParsedTopic& topic, const std::string& payload) {
        if (topic.dev == dev) return;
        auto notify = decode<NotifyState>(payload);
        if (!notify || notify->state != "offline") return;
        if (applications->gone(topic.dev)) application_gone(topic.dev, "Notify/State offline");
    }

    // ------------------------------------------------------------- requests

    // Thread: transport callback. Filters, then hands the work to a request
    // worker; never blocks on the driver.
    void on_message(const Message& message) {
        const auto parsed = parse_topic(message.topic);
        if (!parsed) return;
        if (parsed->kind == TopicKind::register_response) {
            on_register_response(message.payload);
            return;
        }
        if (parsed->kind == TopicKind::notify_state) {
            on_notify_state(*parsed, message.payload);
            return;
        }
        if (!response_kind(parsed->kind) || parsed->kind == TopicKind::probe_version ||
            parsed->kind == TopicKind::register_request || parsed->kind == TopicKind::discovery_request)
            return;  // not a request to an adapter (version-check answers and the like)
        if (parsed->dev != dev) return;
        if (parsed->ex) applications->seen(*parsed->ex, clock->now());
        if (message.retained) {
            // A retained request is replayed by the broker to every new
            // subscription: acting on it would repeat a stale Set.
            ++ignored_retained;
            logger.warn("ignoring retained request on {}", message.topic);
            return;
        }
        const MessageId msg_id = peek_message_id(message.payload);
        if (msg_id) {
            const std::string key = fmt::format("{}|{}|{}", to_string(parsed->kind), parsed->ex.value_or(""), msg_id->dump());
            if (!dedup->first_sighting(key)) {
                ++ignored_duplicates;
                logger.debug("ignoring repeated request {} on {}", msg_id->dump(), message.topic);
                return;
            }
        }
        if (parsed->kind == TopicKind::query_request && dispatch_driver_affine(*parsed, message.payload)) return;
        executor->post([this, topic = *parsed, payload = message.payload] { handle(topic, payload); });
    }

    // A Query runs on the driver's own worker, which reads in place: one
    // thread hand-off fewer than request worker -> driver worker -> back
    // (bench_query_roundtrip: 100 items went from ~1.8x to ~1.55x the bare
    // paho floor). The worker cannot give up on a stuck driver, so the
    // watchdog answers for it at the deadline: on a request worker, with 203
    // for the driver's items. Whichever comes first answers; the other is
    // dropped. Reads are idempotent, so the late duplicate work is harmless;
    // Set stays on the request workers, where a write is never repeated.
    bool dispatch_driver_affine(const ParsedTopic& topic, const std::string& payload) {
        auto claim = std::make_shared<detail::AnswerClaim>();
        const bool posted = runner->post([this, life = lifetime, claim, topic, payload](Driver&) {
            handle(topic, payload, Affine{claim.get(), life.get()});
        });
        if (!posted) return false;
        watchdog->arm(std::chrono::steady_clock::now() + config.driver_timeout, [this, claim, topic, payload] {
            if (!claim->claim_for_deadline()) return;
            ++affine_timeouts;
            logger.warn("driver '{}' did not answer a Query within {} ms", driver->info().name, config.driver_timeout.count());
            executor->post([this, topic, payload] {
                const Error expired = make_error(ErrorCode::timeout, fmt::format("driver did not answer within {} ms",
                                                                                 config.driver_timeout.count()));
                handle(topic, payload, Affine{nullptr, nullptr}, &expired);
            });
        });
        return true;
    }

    // Thread: request worker, or the driver's worker for a driver-affine Query.
    void handle(const ParsedTopic& topic, const std::string& payload) { handle(topic, payload, Affine{nullptr, nullptr}); }
    void handle(const ParsedTopic& topic, const std::string& payload, Affine affine,
                const Error* driver_expired = nullptr) {
        ++requests;
        const auto current = host.current();
        // Copies, not references into the adapter: a driver-affine task may
        // outlive it (see Lifetime).
        const Logger task_logger = logger;
        const std::string task_dev = dev;
        // config.sampling.stats_item: the SDK-provided statistics item (docs/sampling.md)
        detail::HandlerContext context{*current, *runner, host, task_dev, task_logger, config.sampling.stats_item,
                                       [this] { return to_json(self->stats()); }, driver_expired};
        std::optional<Json> reply;
        switch (topic.kind) {
            case TopicKind::query_request:
                reply = answer<QueryRequest>(topic, payload, [&](const QueryRequest& r) { return to_json(detail::handle_query(r, context)); });
                break;
            case TopicKind::set_request:
                reply = answer<SetRequest>(topic, payload, [&](const SetRequest& r) { return to_json(detail::handle_set(r, context)); });
                break;
            case TopicKind::probe_query_request:
                reply = answer<ProbeQueryRequest>(topic, payload, [&](const ProbeQueryRequest& r) {
                    return to_json(detail::handle_probe_query(r, context));
                });
                break;
            case TopicKind::probe_set_request:
                reply = answer<ProbeSetRequest>(topic, payload, [&](const ProbeSetRequest& r) { return to_json(probe_set(r)); });
                break;
            default:
                for (auto& service : services) {
                    if (service->handles(topic.kind)) {
                        service->handle(topic, payload);
                        return;
                    }
                }
                // Requests of features this adapter does not run: never
                // silence, always an answer (WIRE.md).
                ++rejected;
                reply = make_error_reply(topic.kind, peek_message_id(payload), dev,
                                         make_error(ErrorCode::unavailable, "not supported by this adapter"));
                break;
        }
        if (!reply) return;
        if (!affine.claim) {
            respond(topic, *reply);
            return;
        }
        std::lock_guard<std::mutex> alive_lock(affine.life->mutex);
        if (!affine.life->alive) return;  // the adapter is gone
        if (!affine.claim->claim_for_worker()) {
            logger.debug("late Query answer on {} dropped: the deadline answered it", to_string(topic.kind));
            return;
        }
        respond(topic, *reply);
    }

    template <class Request, class Handler>
    std::optional<Json> answer(const ParsedTopic& topic, const std::string& payload, Handler&& handler) {
        auto request = decode<Request>(payload);
        if (!request) {
            ++rejected;
            logger.info("malformed {} answered NG: {}", to_string(topic.kind), request.error().describe());
            return make_error_reply(topic.kind, peek_message_id(payload), dev, request.error());
        }
        return handler(request.value());
    }

    void respond(const ParsedTopic& request_topic, const Json& reply) {
        const std::string payload = reply.dump(-1, ' ', false, Json::error_handler_t::replace);
        bool ok = true;
        for (const auto& topic : response_topics(request_topic, config.standard_typo_topics))
            ok = transport->publish(Message{topic, payload, 1, false}).ok() && ok;
        fire(ok ? AdapterEvent::request_answered : AdapterEvent::request_answer_failed);
    }

    ProbeSetResponse probe_set(const ProbeSetRequest& request) {
        auto response = make_reply<ProbeSetResponse>(request, dev);
        const std::string text = request.probe.is_string() ? request.probe.get<std::string>()
                                                           : request.probe.dump(-1, ' ', false, Json::error_handler_t::replace);
        LoadResult loaded = parse_model(text);
        const std::string refused = detail::refusal_reasons(loaded, config.strict);
        if (!refused.empty()) {
            // Every problem in `reason` (WIRE.md/issue: the sender fixes all in one round).
            response.status = ResponseStatus::failure(refused, to_int(ErrorCode::syntax_error));
            return response;
        }
        auto built = host.build(loaded, config.device_id, *driver);
        if (!built) {
            response.status = ResponseStatus(built.error());
            return response;
        }
        const std::string new_dev = resolve_dev_uuid(*built.value()->device, config.dev_uuid);
        if (new_dev != dev)
            logger.warn("the new model names the device {}, this adapter keeps answering as {}", new_dev, dev);
        if (auto persisted = host.persist_model(serialize_model(*built.value()->model)); !persisted) {
            response.status = ResponseStatus(persisted.error());
            return response;
        }
        host.install(built.value());
        logger.info("model replaced by Probe/Set: version {}", built.value()->device->version);
        std::vector<ModelListener> to_call;
        {
            std::lock_guard<std::mutex> lock(mutex);
            to_call = listeners;
        }
        for (auto& service : services) service->on_model(built.value());
        for (auto& listener : to_call) listener(built.value()->model);
        publish_version();
        return response;
    }
};

Adapter::Adapter(AdapterConfig config, std::shared_ptr<Driver> driver, Logger logger)
    : impl_(std::make_unique<Impl>(std::move(config), std::move(driver), std::move(logger))) {
    impl_->self = this;
}

Adapter::~Adapter() { stop(std::chrono::milliseconds(500)); }

void Adapter::use_transport(std::unique_ptr<Transport> transport) { impl_->transport = std::move(transport); }
void Adapter::use_clock(std::shared_ptr<const Clock> clock) { impl_->clock = std::move(clock); }
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

AdapterStats Adapter::stats() const {
    AdapterStats s;
    s.requests = impl_->requests;
    s.ignored_retained = impl_->ignored_retained;
    s.ignored_duplicates = impl_->ignored_duplicates;
    s.rejected = impl_->rejected;
    s.driver_timeouts = (impl_->runner ? impl_->runner->timeouts() : 0) + impl_->affine_timeouts;
    s.registered = impl_->registered;
    s.state = state();
    if (impl_->transport) s.transport = impl_->transport->stats();
    for (const auto& service : impl_->services) s.features[std::string(service->name())] = service->stats();
    return s;
}

void Adapter::notify_value(const std::string& id, Json value) {
    if (!impl_->services_ready.load(std::memory_order_acquire)) return;
    for (const auto& service : impl_->services) service->on_value(id, value);
}

namespace {
detail::SamplingService* sampling_service(const std::vector<std::unique_ptr<detail::Feature>>& services) {
    for (const auto& service : services)
        if (auto* sampling = dynamic_cast<detail::SamplingService*>(service.get())) return sampling;
    return nullptr;
}
}  // namespace

Result<PushChannel> Adapter::push_channel(const std::string& channel_id) const {
    auto* sampling = impl_->services_ready.load(std::memory_order_acquire) ? sampling_service(impl_->services) : nullptr;
    if (!sampling || !impl_->config.sampling.enabled)
        return make_error(ErrorCode::unavailable, "sampling is not running (adapter not started, or sampling.enabled is false)");
    return sampling->push_channel(channel_id);
}

SamplingStats Adapter::sampling_stats() const {
    auto* sampling = impl_->services_ready.load(std::memory_order_acquire) ? sampling_service(impl_->services) : nullptr;
    return sampling ? sampling->typed_stats() : SamplingStats{};
}

Json to_json(const AdapterStats& s) {
    const auto& t = s.transport;
    return Json{{"requests", s.requests},
                {"ignored_retained", s.ignored_retained},
                {"ignored_duplicates", s.ignored_duplicates},
                {"rejected", s.rejected},
                {"driver_timeouts", s.driver_timeouts},
                {"registered", s.registered},
                {"state", std::string(to_string(s.state))},
                {"transport", {{"published", t.published}, {"received", t.received}, {"dropped", t.dropped},
                               {"dropped_bytes", t.dropped_bytes}, {"connects", t.connects}, {"buffered", t.buffered},
                               {"buffered_bytes", t.buffered_bytes}, {"in_flight", t.in_flight}}},
                {"features", s.features}};
}

void Adapter::add_model_listener(ModelListener listener) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->listeners.push_back(std::move(listener));
}

}  // namespace nclink
