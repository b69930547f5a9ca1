// The adapter's insides, shared by the files that implement it, one
// responsibility each:
//   adapter.cpp           the public facade and the lifecycle (start/stop,
//                         model load, driver open, transport, features)
//   adapter_link.cpp      the link: online state, registration, Probe/Version,
//                         the state-machine state machine, application liveness
//   adapter_requests.cpp  request intake: filters (retain, dedup), routing to
//                         a worker or the driver's worker, answers
//   adapter_probe_set.cpp Probe/Set: a new model validated, persisted, swapped
//   adapter_stats.cpp     statistics
//   adapter_metrics.cpp   traffic (DTUs by kind, request latency) and the
//                         Prometheus text of the statistics
// Nothing outside src/adapter/ includes this.
#pragma once

#include "adapter/application_tracker.hpp"
#include "adapter/dedup_window.hpp"
#include "adapter/drop_reporter.hpp"
#include "adapter/model_host.hpp"
#include "adapter/registration.hpp"
#include "adapter/response_cache.hpp"
#include "adapter/request_gate.hpp"
#include "core/deadline_watchdog.hpp"
#include "core/latency_histogram.hpp"
#include "core/executor.hpp"
#include "core/poll_host.hpp"
#include "core/task_group.hpp"
#include "core/watchdog_scope.hpp"
#include "driver/driver_runner.hpp"
#include "feature/feature.hpp"
#include "transport/dtu_counting_transport.hpp"

#include <nclink/adapter.hpp>
#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace nclink {

/// How often housekeeping looks at registration retries, leases and drops
/// (real time; the registration and lease clocks are the injected clock).
inline constexpr std::chrono::milliseconds kHousekeepingPeriod{50};
/// The same on shared timer threads (gateway mode, real clock only): a
/// thousand machines at 50 ms would be 20,000 passes a second for retries
/// measured in seconds and leases in minutes.
inline constexpr std::chrono::milliseconds kSharedHousekeepingPeriod{250};

struct NCLINK_LOCAL Adapter::Impl {
    Impl(AdapterConfig c, std::shared_ptr<Driver> d, Logger l)
        : config(std::move(c)),
          logger(std::move(l)),
          driver(std::move(d)),
          host(config.persistence_dir, logger),
          registration(config.register_timeout, config.register_retry_max) {}

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
    std::unique_ptr<detail::DriverRunner> runner;
    std::shared_ptr<SharedThreads> shared_threads;  // gateway mode; null: the adapter's own threads
    std::shared_ptr<detail::Executor> own_executor;  // without shared_threads
    std::unique_ptr<detail::TaskGroup> executor;     // this adapter's request tasks (on either)
    std::unique_ptr<detail::DedupWindow> dedup;
    std::shared_ptr<detail::RequestGate> gate;  // bounded request intake (request_gate.hpp)
    std::unique_ptr<detail::DeadlineWatchdog> own_watchdog;  // without shared_threads
    std::unique_ptr<detail::WatchdogScope> watchdog;         // this adapter's deadlines (on either)
    std::shared_ptr<Lifetime> lifetime = std::make_shared<Lifetime>();
    /// Chapter 7 checks of driver values (shared: a driver-affine task may outlive the adapter).
    std::shared_ptr<detail::ValueGuard> value_guard = std::make_shared<detail::ValueGuard>(logger, config.check_values);
    std::string dev;
    std::string msg_id_prefix;
    std::string instance;  ///< this run of the adapter, in Probe/Version's privateInfo (docs/wire.md)

    // ---- features (sampling, events, methods): see feature/feature.hpp
    detail::SampleTap sample_tap;
    std::unique_ptr<detail::FeatureHost> feature_host;
    std::vector<std::unique_ptr<detail::Feature>> features;
    std::atomic<bool> features_ready{false};  // set once `features` is complete and started
    std::unique_ptr<detail::ApplicationTracker> applications;

    // ---- state (mutex)
    mutable std::mutex mutex;
    AdapterState state = AdapterState::initial;
    bool connected_once = false;  // a link_lost before it is the transport's start, not a loss
    detail::ResponseCache responses{config.offline_buffer_bytes};  // state-machine text items 75, 79: kept while the link will not take them
    std::vector<ModelListener> listeners;
    bool started = false;
    bool stopped = false;

    // ---- housekeeping thread: registration retries, application leases
    detail::Registration registration;
    std::mutex housekeeping_mutex;
    std::condition_variable housekeeping_wake;
    bool housekeeping_stopping = false;
    std::thread housekeeping;                  // without shared_threads
    detail::PollHost::Handle housekeeping_entry;  // with shared_threads
    detail::DropReporter drop_reporter{logger};  // housekeeping only
    std::chrono::steady_clock::time_point last_drop_check{};  // housekeeping only

    std::atomic<std::uint64_t> requests{0}, ignored_retained{0}, ignored_duplicates{0}, rejected{0}, msg_counter{0},
        affine_timeouts{0}, applications_released{0};

    // ---- traffic (adapter_metrics.cpp): DTUs by kind, request latency by kind
    std::shared_ptr<detail::DtuCounter> dtus = std::make_shared<detail::DtuCounter>();
    std::array<detail::LatencyHistogram, detail::kTopicKindCount> request_latency;
    /// A request of `kind` received at `received` was handled (any thread).
    void observe_request(TopicKind kind, std::chrono::steady_clock::time_point received) noexcept;

    // ---- lifecycle (adapter.cpp), owner thread
    Result<void> start();
    void stop(std::chrono::milliseconds flush_timeout);
    Result<LoadResult> load_model();
    MqttOptions mqtt_options() const;
    Message state_message(const char* state_text) const;
    Result<void> make_features();

    // ---- the link (adapter_link.cpp)
    void on_link(LinkState link, std::string_view detail);  ///< transport thread; never blocks
    /// Runs the state-machine table: takes the row of (state, event), moves to
    /// its next state and performs its actions. `response` is the response
    /// at hand for request_handled/response_failed. Any thread.
    void fire(AdapterEvent event, std::vector<Message> response = {});
    void flush_responses();
    std::string next_msg_id();
    void send_registration();
    void publish_version();
    void housekeep();  ///< the housekeeping thread's loop (own threads)
    void housekeep_once();  ///< one pass of it (also a pollable on shared threads)
    /// The statistics' "drops" object, read from the counters (thread-safe).
    Json drops_now() const;
    void wake_housekeeping();
    void on_register_response(const std::string& payload);
    void application_gone(const std::string& ex, std::string_view why);
    void on_notify_state(const ParsedTopic& topic, const std::string& payload);
    /// Subscribes the Notify/State of an application that just sent its
    /// first DTU, to release what it registered when it goes offline.
    void watch_application(const std::string& ex);

    // ---- requests (adapter_requests.cpp)
    void on_message(const Message& message);  ///< transport thread; never blocks
    /// A Query or Set already decoded on the transport thread, which parses
    /// it for its @id anyway: the worker then does not parse it again.
    /// Both null when it was not (another kind, or a payload left to the
    /// worker's decoder, which gives the table-19 answer).
    struct Decoded {
        std::shared_ptr<const QueryRequest> query;
        std::shared_ptr<const SetRequest> set;
    };
    bool dispatch_driver_affine(const ParsedTopic& topic, const std::string& payload,
                                std::shared_ptr<detail::RequestGate::Ticket> ticket,
                                std::chrono::steady_clock::time_point received, Decoded decoded);
    void handle(const ParsedTopic& topic, const std::string& payload);
    void handle(const ParsedTopic& topic, const std::string& payload, Affine affine,
                const Error* driver_expired = nullptr, const Decoded& decoded = {});
    template <class Request, class Handler>
    std::optional<Json> answer(const ParsedTopic& topic, const std::string& payload, Handler&& handler);
    /// The NG answer to an undecodable request (counted and logged).
    std::optional<Json> malformed(const ParsedTopic& topic, const std::string& payload, const Error& error);
    void respond(const ParsedTopic& request_topic, const Json& reply);
    /// respond() with the payload already serialized (Probe/Query's verbatim model).
    /// Publishes `payload` on the response topic(s); taken by value: the
    /// last topic's message takes it over (a Query answer can be megabytes).
    void respond_text(const ParsedTopic& request_topic, std::string payload);

    // ---- Probe/Set (adapter_probe_set.cpp)
    ProbeSetResponse probe_set(const ProbeSetRequest& request);
    /// Validates, persists and swaps in a whole model (Probe/Set and
    /// Adapter::replace_model/patch_model); returns its version. `origin`
    /// names the caller in logs.
    Result<std::string> adopt_model(const std::string& text, std::string_view origin);
    std::mutex model_change_mutex;  // one model change at a time: binds and installs come in one order
    /// Binds the model in force again (after a Probe/Set that was bound but
    /// not installed) and installs that copy.
    void rebind_current();
};

}  // namespace nclink
