// Request intake, one object: every request DTU that reaches the adapter is
// filtered (retain flag, repeated @id, not for this device), admitted within
// the bounds of request_gate.hpp, handed to a request worker (or, for a
// Query or a Set, to the driver's own worker, with a deadline the watchdog
// keeps), decoded, answered, and the answer handed to the link
// (AdapterLink::respond), which sends or keeps it. It owns the request
// workers, the deadline watchdog, the dedup window and the request counters.
//
// Threads: on_request() on the transport's callback thread (never blocks on
// the driver); the handling on a request worker or the driver's worker; the
// deadline answers on the watchdog's thread, then a request worker.
// counts()/add_latency() on any thread.
#pragma once

#include "adapter/adapter_applications.hpp"
#include "adapter/adapter_features.hpp"
#include "adapter/adapter_link.hpp"
#include "adapter/adapter_model_change.hpp"
#include "adapter/dedup_window.hpp"
#include "adapter/model_host.hpp"
#include "adapter/request_gate.hpp"
#include "core/deadline_watchdog.hpp"
#include "core/executor.hpp"
#include "core/latency_histogram.hpp"
#include "core/shared_threads_impl.hpp"
#include "core/task_group.hpp"
#include "core/watchdog_scope.hpp"
#include "driver/driver_runner.hpp"
#include "feature/value_guard.hpp"
#include "transport/dtu_counting_transport.hpp"  // kTopicKindCount

#include <nclink/adapter_config.hpp>
#include <nclink/dtu.hpp>
#include <nclink/log.hpp>
#include <nclink/topics.hpp>
#include <nclink/traffic_stats.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace nclink::adapter_detail {

class RequestIntake {
public:
    /// What the intake works with; every reference outlives it.
    struct Parts {
        const AdapterConfig& config;
        const Logger& logger;
        const std::string& dev;
        std::shared_ptr<const Clock> clock;
        const Driver& driver;  ///< its name, in the deadline's log line
        driver_detail::DriverRunner& runner;
        ModelHost& host;
        std::shared_ptr<feature_detail::ValueGuard> values;  ///< shared: a driver-affine task may outlive the adapter
        AdapterLink& link;
        FeatureSet& features;
        ApplicationWatch& applications;
        ModelChange& model_change;
        std::function<Json()> statistics;       ///< the statistics item's value (SamplingConfig::stats_item)
        SharedThreads::Impl* shared = nullptr;  ///< gateway mode; null: workers and watchdog of its own
        /// Without `shared`: the adapter's background threads, where its own
        /// deadline watchdog runs (null: a thread of its own).
        core_detail::PollHost* background = nullptr;
    };
    explicit RequestIntake(Parts parts);

    /// A request DTU for this adapter's kinds (the transport callback thread).
    void on_request(const ParsedTopic& topic, const Message& message);
    /// No new work: the deadlines are dropped, what is queued is answered.
    /// Owner thread, before the features and the transport stop.
    void close();
    /// After the driver runner stopped: a driver-affine task still inside a
    /// stuck driver must not answer through a destroyed adapter when it
    /// comes back.
    void release_driver_tasks();

    struct Counts {
        std::uint64_t requests = 0, ignored_retained = 0, ignored_duplicates = 0, rejected = 0, affine_timeouts = 0;
        std::uint64_t shed = 0, oversized = 0;
        std::size_t pending = 0;
    };
    Counts counts() const;
    /// Requests shed so far (the statistics' drops.requests_shed).
    std::uint64_t shed() const { return gate_->shed(); }
    /// Request latency by kind (TrafficStats::request_seconds).
    void add_latency(TrafficStats& out) const;

private:
    // Lets a driver-affine task that returns from a stuck driver after the
    // adapter is gone (its worker was abandoned at stop) see that, instead of
    // touching a destroyed adapter.
    struct Lifetime {
        std::mutex mutex;
        bool alive = true;
    };
    struct Affine {
        core_detail::AnswerClaim* claim = nullptr;  ///< null: not a driver-affine task
        Lifetime* life = nullptr;
    };
    /// A Query or Set already decoded on the transport thread, which parses
    /// it for its @id anyway: the worker then does not parse it again.
    /// Both null when it was not (another kind, or a payload left to the
    /// worker's decoder, which gives the table-19 answer).
    struct Decoded {
        std::shared_ptr<const QueryRequest> query;
        std::shared_ptr<const SetRequest> set;
    };

    bool dispatch_driver_affine(const ParsedTopic& topic, const std::string& payload, std::shared_ptr<RequestGate::Ticket> ticket,
                                std::chrono::steady_clock::time_point received, Decoded decoded);
    void handle(const ParsedTopic& topic, const std::string& payload);
    void handle(const ParsedTopic& topic, const std::string& payload, Affine affine, const Error* driver_expired = nullptr,
                const Decoded& decoded = {});
    template <class Request, class Handler>
    std::optional<Json> answer(const ParsedTopic& topic, const std::string& payload, Handler&& handler);
    /// The NG answer to an undecodable request (counted and logged).
    std::optional<Json> malformed(const ParsedTopic& topic, const std::string& payload, const Error& error);
    /// A request of `kind` received at `received` was handled (any thread).
    void observe(TopicKind kind, std::chrono::steady_clock::time_point received) noexcept;

    Parts parts_;
    std::shared_ptr<core_detail::Executor> own_executor_;          // without shared threads
    std::unique_ptr<core_detail::TaskGroup> executor_;             // this adapter's request tasks (on either)
    std::unique_ptr<core_detail::DeadlineWatchdog> own_watchdog_;  // without shared threads
    std::unique_ptr<core_detail::WatchdogScope> watchdog_;         // this adapter's deadlines (on either)
    std::shared_ptr<RequestGate> gate_;                            // bounded request intake (its own lock)
    DedupWindow dedup_;                                            // its own lock
    std::shared_ptr<Lifetime> lifetime_ = std::make_shared<Lifetime>();
    std::atomic<std::uint64_t> requests_{0}, ignored_retained_{0}, ignored_duplicates_{0}, rejected_{0}, affine_timeouts_{0};
    std::array<core_detail::LatencyHistogram, transport_detail::kTopicKindCount> latency_;
};

}  // namespace nclink::adapter_detail
