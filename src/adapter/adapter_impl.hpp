// The adapter's insides: a small composition of objects with one job each,
// each owning its state and its lock (a file pair per object):
//   adapter_link.hpp          AdapterLink: the state machine, the responses
//                             it keeps, online state, registration,
//                             Probe/Version; every answer goes out through it
//   adapter_requests.hpp      RequestIntake: filters, admission, workers,
//                             driver deadlines, the request counters
//   adapter_model_change.hpp  ModelChange: Probe/Set and replace_model/
//                             patch_model, one at a time; ModelListeners
//   adapter_applications.hpp  ApplicationWatch: application liveness (8.2.18.3)
//   adapter_housekeeping.hpp  Housekeeping: the periodic pass (registration
//                             retries, leases, kept responses, drop reports)
//   adapter_features.hpp      FeatureSet: the running features, and the one
//                             list of which features there are
// and the Impl below, which builds them in start() and stops them in stop():
//   adapter.cpp               the public facade and the lifecycle
//   adapter_model_load.cpp    which model file a start serves
//   adapter_stats.cpp         statistics (AdapterStats, its JSON, the drops)
//   adapter_metrics.cpp       traffic and the Prometheus text
//   adapter_config.cpp, adapter_reload.cpp: the configuration file, reload
//   adapter_state.cpp         the state machine's table (AdapterLink runs it)
// Helpers without threads: model_host, registration, request_gate,
// request_handlers, dedup_window, response_cache, application_tracker,
// drop_reporter; run_adapter.cpp is the program around an adapter.
//
// Threads and who serves them:
// - owner thread (start/stop/reload): Impl.
// - transport callback thread: Impl::on_message routes a Register/Response
//   to AdapterLink, a Notify/State to ApplicationWatch, requests to
//   RequestIntake; Impl::on_link tells AdapterLink, then FeatureSet.
// - request workers and the driver's worker: RequestIntake (Probe/Set via
//   ModelChange; feature requests via FeatureSet), answers via AdapterLink.
// - the watchdog thread: RequestIntake's deadline answers.
// - the housekeeping thread (or a shared timer): Housekeeping.
// - firmware threads: replace_model/patch_model (ModelChange), notify_value
//   (FeatureSet); stats() and the others from any thread.
// Nothing outside src/adapter/ includes this.
#pragma once

#include "adapter/adapter_applications.hpp"
#include "adapter/adapter_features.hpp"
#include "adapter/adapter_housekeeping.hpp"
#include "adapter/adapter_link.hpp"
#include "adapter/adapter_model_change.hpp"
#include "adapter/adapter_requests.hpp"
#include "adapter/model_host.hpp"
#include "driver/driver_runner.hpp"
#include "feature/value_guard.hpp"
#include "transport/dtu_counting_transport.hpp"

#include <nclink/adapter.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

namespace nclink {

struct NCLINK_LOCAL Adapter::Impl {
    Impl(AdapterConfig c, std::shared_ptr<Driver> d, Logger l)
        : config(std::move(c)), logger(std::move(l)), driver(std::move(d)), host(config.persistence_dir, logger) {}

    // ---- configuration and collaborators (set before start, or in start before `composed`)
    const Adapter* self = nullptr;  // the owner, for its stats() (the statistics data item)
    AdapterConfig config;           // as started: never written after construction
    Logger logger;
    std::shared_ptr<Driver> driver;
    /// A single adapter's background threads ("nclink-work", without
    /// shared_threads): its outbox's sender, sample uploader, events engine,
    /// method status ticker, spool, housekeeping and deadline watchdog, each
    /// a pollable (core/poll_host.hpp), instead of a thread each
    /// (docs/footprint.md, "Where the threads go"). Declared before
    /// `transport` and the objects, which remove their pollables when they
    /// go: the host goes after them.
    std::unique_ptr<core_detail::PollHost> background;
    /// Two: the events engine may wait in a driver read for up to the
    /// driver's deadline; what falls due meanwhile (a Sample DTU to publish,
    /// a request's deadline) is taken by the other thread after
    /// PollHost::kBackstop (5 ms) instead.
    static constexpr std::size_t kBackgroundThreads = 2;
    std::unique_ptr<Transport> transport;
    std::shared_ptr<const Clock> clock = std::make_shared<SystemClock>();
    std::shared_ptr<SharedThreads> shared_threads;  // gateway mode; null: the adapter's own threads
    adapter_detail::ModelHost host;
    std::unique_ptr<driver_detail::DriverRunner> runner;
    /// Chapter 7 checks of driver values (shared: a driver-affine task may outlive the adapter).
    std::shared_ptr<feature_detail::ValueGuard> value_guard =
        std::make_shared<feature_detail::ValueGuard>(logger, config.check_values);
    std::shared_ptr<transport_detail::DtuCounter> dtus = std::make_shared<transport_detail::DtuCounter>();  // DTUs by kind
    std::string dev;

    // ---- lifecycle (mutex)
    std::mutex mutex;
    bool started = false;
    bool stopped = false;
    std::mutex reload_mutex;
    LogLevel reloaded_level = config.log_level;  // under reload_mutex: the level the last reload set

    // ---- the objects; built in start(), in this order, then `composed` is
    // set and they stay until the Impl goes (threads stop in stop()).
    adapter_detail::ModelListeners listeners;  // from construction: listeners come before start()
    adapter_detail::FeatureSet features;
    std::unique_ptr<adapter_detail::AdapterLink> link;
    std::unique_ptr<adapter_detail::ApplicationWatch> applications;
    std::unique_ptr<adapter_detail::ModelChange> model_change;
    std::unique_ptr<adapter_detail::RequestIntake> requests;
    std::unique_ptr<adapter_detail::Housekeeping> housekeeping;
    std::atomic<bool> composed{false};

    // ---- lifecycle (adapter.cpp), owner thread
    Result<void> start();
    void stop(std::chrono::milliseconds flush_timeout);
    MqttOptions mqtt_options() const;
    /// Whether a model change may run: started, not stopping, initialized.
    bool running();
    void on_message(const Message& message);  ///< transport thread; never blocks
    void on_link(LinkState link);             ///< transport thread; never blocks
    /// Adds the causes of the statistics' "drops" object, read from the
    /// counters (thread-safe; housekeeping's once-a-second look).
    void add_drops_now(feature_detail::DropCounts& out) const;
};

}  // namespace nclink
