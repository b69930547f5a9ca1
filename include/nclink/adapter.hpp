// The adapter: a machine on NC-Link. Give it a configuration and a driver;
// it loads and validates the model, connects to the broker, announces itself
// (retained online state with an offline last will, Register/Request,
// Probe/Version) and answers Probe/Query, Probe/Set, Query and Set.
//
//   nclink::AdapterConfig config = nclink::load_adapter_config("adapter.json").value();
//   nclink::Adapter adapter(config, std::make_shared<MyDriver>(), logger);
//   if (auto started = adapter.start(); !started) { ...started.error()... }
//   ... adapter.stop();
//
// Threading: start() and stop() are called by the owner (not concurrently,
// not from a driver callback). Every other public call is thread-safe.
// Requests are handled on the adapter's request workers, never on the MQTT
// callback thread; drivers are called on their own workers (driver.hpp).
// With use_shared_threads() those workers belong to a SharedThreads pool that
// several adapters use; calls into one driver stay serialized either way.
#pragma once

#include <nclink/adapter_config.hpp>
#include <nclink/config_reload.hpp>
#include <nclink/adapter_state.hpp>
#include <nclink/clock.hpp>
#include <nclink/driver.hpp>
#include <nclink/export.hpp>
#include <nclink/log.hpp>
#include <nclink/model.hpp>
#include <nclink/model_cache.hpp>
#include <nclink/sampling.hpp>
#include <nclink/shared_threads.hpp>
#include <nclink/traffic_stats.hpp>
#include <nclink/transport.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nclink {

struct NCLINK_API AdapterStats {
    std::uint64_t requests = 0;            ///< request DTUs handled
    std::uint64_t ignored_retained = 0;    ///< requests ignored for their retain flag
    std::uint64_t ignored_duplicates = 0;  ///< requests ignored as a repeated @id
    std::uint64_t rejected = 0;            ///< requests answered NG as a whole (malformed)
    std::uint64_t driver_timeouts = 0;
    /// Driver values refused for breaking chapter 7 (their item's type,
    /// enumeration, keys or range; docs/porting-guide.md), and how many
    /// items they belonged to.
    std::uint64_t values_refused = 0;
    std::uint64_t values_refused_items = 0;
    /// Applications judged offline (GB/T 41970 3.22: silent for the
    /// application lease, or their Notify/State offline) whose events and
    /// dynamic channels were released (docs/delivery.md, "Liveness").
    std::uint64_t applications_released = 0;
    /// Driver::link() now: while disconnected, driver items answer 202
    /// "machine disconnected: <reason>" without a driver call.
    MachineLinkStatus machine_link;
    std::uint64_t shed = 0;            ///< requests dropped unanswered: max_pending_requests were pending
    std::uint64_t oversized = 0;       ///< requests answered 404 unread: above max_request_bytes
    std::size_t pending_requests = 0;  ///< requests waiting or being handled now
    bool registered = false;           ///< an agent accepted Register/Request
    AdapterState state = AdapterState::initial;
    TransportStats transport;
    /// Counters of the features (sampling, events, methods), one object each,
    /// keyed by feature name.
    Json features = Json::object();
};

/// The statistics as one JSON object (what the `nclink_stats` data item and
/// `nclink stats` show; docs/sampling.md). Its "drops" object sums every
/// loss by cause (docs/delivery.md, "Counted drops").
NCLINK_API Json to_json(const AdapterStats& stats);

/// Called after a Probe/Set replaced the model (on a request worker). Later
/// modules (sampling, events) restart what runs from the model here.
using ModelListener = std::function<void(std::shared_ptr<const Model>)>;

class NCLINK_API Adapter {
public:
    /// `driver` may be null when `config.driver_plugin` names a plugin.
    Adapter(AdapterConfig config, std::shared_ptr<Driver> driver, Logger logger = {});
    ~Adapter();
    Adapter(const Adapter&) = delete;
    Adapter& operator=(const Adapter&) = delete;

    /// For tests and special links: use this transport instead of MQTT (set
    /// before start()). The adapter owns it from then on.
    void use_transport(std::unique_ptr<Transport> transport);
    /// For tests: the clock for dedup windows and registration retries.
    void use_clock(std::shared_ptr<const Clock> clock);
    /// Gateway mode: take the sampling scheduler, uploader, housekeeping,
    /// request workers and deadline watchdog from `threads` (shared with
    /// other adapters of the process) instead of starting them (set before
    /// start(); include/nclink/shared_threads.hpp says what stays per
    /// adapter). `threads` must outlive the adapter's stop().
    void use_shared_threads(std::shared_ptr<SharedThreads> threads);
    /// Gateway mode: load the model file through `cache`, shared with the
    /// other adapters of the process, so machines of one model file share
    /// one parsed model and its value rules (nclink/model_cache.hpp; set
    /// before start()).
    void use_model_cache(std::shared_ptr<ModelCache> cache);

    /// Loads and validates the model (refusing fatal problems, and
    /// conformance problems when strict, listing every one), opens the
    /// driver, connects and starts serving. Returns when serving has begun;
    /// the broker may still be unreachable (the adapter keeps trying).
    Result<void> start();
    /// Publishes the offline state, flushes what is buffered (up to
    /// `flush_timeout`), disconnects, stops the driver. Idempotent.
    void stop(std::chrono::milliseconds flush_timeout = std::chrono::milliseconds(2000));

    /// Applies a new configuration as far as that is safe while running (a
    /// program's SIGHUP, docs/configuration.md "Reloading"): log_level sets
    /// the logger's level (shared with every copy of the logger). Every other
    /// changed key is listed in restart_needed and keeps its running value.
    /// Thread-safe; also before start().
    ConfigReload reload(const AdapterConfig& next);
    /// The terminal id (dev_uuid) this adapter answers for.
    std::string dev_uuid() const;
    std::shared_ptr<const Model> model() const;
    /// Problems found in the current model (conformance and warnings).
    std::vector<Problem> model_problems() const;
    AdapterState state() const;
    AdapterStats stats() const;

    void add_model_listener(ModelListener listener);

    /// Replaces the model at run time (a new tool, an added axis): `model_json`
    /// is a whole model file's text. It is validated exactly as at start (and
    /// as Probe/Set, 8.2.9.3: fatal problems, and conformance problems when
    /// strict, refuse it with every problem listed; nothing changes then),
    /// persisted, and swapped in atomically: a request is answered entirely
    /// from the old model or entirely from the new one. Then Probe/Version is
    /// announced (8.2.5.3; when the link is down, on reconnection), model
    /// sample channels are re-planned, and event registrations and dynamic
    /// channels whose items no longer resolve are released, each owner told
    /// with 401 (docs/wire.md). Returns the new model's version.
    /// Errors: 412 invalid model, 401 the configured device is not in it,
    /// 202 before start() or after stop(). Thread-safe; serialized with
    /// Probe/Set and itself.
    Result<std::string> replace_model(const std::string& model_json);
    /// The same, from a JSON Patch (RFC 6902: add/remove/replace/move/copy/test
    /// operations) applied to the current model as Probe/Query returns it,
    /// e.g. [{"op":"add","path":"/devices/0/components/-","value":{...}}].
    /// Errors: 405 `patch` is not an array of operations, 413 an operation
    /// does not apply (bad path, failed test), then as replace_model().
    Result<std::string> patch_model(const Json& patch);

    /// Push-mode handle of a model sample channel listed in
    /// SamplingConfig::push_channels (docs/sampling.md). Call after start();
    /// the handle's push() is wait-free and safe from a real-time thread.
    /// Errors: 401 no such channel, 405 not a push-mode channel, 202 not
    /// started or sampling disabled. Thread-safe.
    Result<PushChannel> push_channel(const std::string& channel_id) const;
    /// Statistics of the sample channels (also in stats().features["sampling"]). Thread-safe.
    SamplingStats sampling_stats() const;
    /// DTUs sent and received by topic kind, and request latency by kind
    /// (docs/metrics.md; rendered for Prometheus by adapter_metrics.hpp). Thread-safe.
    TrafficStats traffic_stats() const;

    /// A driver (or the firmware) says item `id` has the whole value `value`
    /// now, e.g. from its own change notification. Events watching the item
    /// (docs/events.md) evaluate it at once instead of waiting for the next
    /// poll. Thread-safe, never blocks on the network or the driver: the value
    /// is queued for the events thread. Ignored before start() has returned
    /// and for items no event watches. Not needed for correctness: unsampled
    /// items are polled anyway (EventsConfig::poll_interval).
    void notify_value(const std::string& id, Json value);

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace nclink
