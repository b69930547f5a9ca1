// The application side of NC-Link (an "application system" in GB/T 41970-2022):
// register with the agent, probe, query and set a device's data items, call
// methods, register events, receive samples, state and version
// notifications, and watch every application's method runs and events.
//
// Thread contract (see docs/client.md):
// - Every public member function is thread-safe and may be called from any
//   thread, concurrently.
// - Every callback (request completions, sample/state/version/method-run/
//   event handlers, the link-state handler) runs on the client's own dispatch thread, one at a
//   time, in arrival order -- never on the transport's callback thread, never
//   on the caller's thread (except: a request made when the client is not
//   running completes at once on the caller's thread with ErrorCode::unavailable).
// - Callbacks may call the async (`*_async`, subscribe_*) functions. They must
//   not call the blocking convenience calls (those return ErrorCode::unavailable
//   at once when called on the dispatch thread: they would wait for the very
//   thread they block). A slow callback delays every other callback and the
//   detection of timeouts, so keep them short.
// - Every request callback is called exactly once: with the answer, with an
//   Error (timeout 203, unavailable 202 for DEV_UNREACHABLE or a stopped
//   client, the table-19 code of a whole-request refusal), never both.
//
// Errors are values; nothing thrown escapes.
#pragma once

#include <nclink/client_state.hpp>
#include <nclink/dtu.hpp>
#include <nclink/export.hpp>
#include <nclink/log.hpp>
#include <nclink/mqtt_transport.hpp>
#include <nclink/result.hpp>
#include <nclink/transport.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink {

// ClientState (include/nclink/client_state.hpp) is the application state
// machine (docs/state-machines.md): initial until the link first comes up, then normal
// (connected, nothing outstanding), request (connected, requests outstanding)
// and disconnected. Requests made while not connected (initial or
// disconnected) are queued by the client and sent, in order, when the link
// comes back; they keep the deadline they got when made, and one that times
// out while queued fails with 203 and is never sent (docs/client.md,
// "State machine").

struct NCLINK_API ClientOptions {
    /// The application's terminal id (ex_cid): cli_uuid when registering and the
    /// last level of every request topic (responses mirror it). Required.
    std::string ex_cid;
    /// Timeout of a request whose RequestOptions give none.
    std::chrono::milliseconds default_timeout{2000};
    /// Requests held at most while the link is down (more fail with 404).
    std::size_t max_queued_requests = 1024;
    /// How long stop() lets the transport flush what is still buffered.
    std::chrono::milliseconds stop_flush_timeout{500};
    /// Liveness (GB/T 41970 3.22): an adapter releases the events and dynamic
    /// channels of an application it has not heard from for its application
    /// lease (adapter default 300 s). While this client holds a registration
    /// at an adapter it queries one registered item there at this interval,
    /// and at once after every reconnect, so the registration lives as long
    /// as the client. Keep it well below the adapter's lease (a third or
    /// less). 0 = off (docs/delivery.md, "Liveness").
    std::chrono::milliseconds keepalive_interval{60000};
    /// Sample and Event DTUs remembered per stream to hand each to the
    /// handlers once (QoS 1 repeats a DTU whose acknowledgement a broken
    /// link lost; docs/delivery.md). 0 = no de-duplication.
    std::size_t duplicate_memory = 4096;
    /// Called on the dispatch thread when the link changes state.
    std::function<void(LinkState)> on_link_state;
    Logger logger;
};

struct NCLINK_API RequestOptions {
    std::optional<std::chrono::milliseconds> timeout;  ///< default: ClientOptions::default_timeout
    std::optional<Json> private_info;                  ///< sent as "privateInfo"
};

/// What came of Register/Request. Registration is an agent feature: without an
/// agent (adapter and application on a bare broker) nobody answers, and the
/// application goes on working, so no answer is an outcome, not an error.
struct NCLINK_API RegisterOutcome {
    enum class Kind { accepted, refused, no_answer };
    Kind kind = Kind::no_answer;
    ResponseStatus status;  ///< the agent's code/reason/error (accepted/refused)
};

NCLINK_API std::string_view to_string(RegisterOutcome::Kind kind) noexcept;

/// Counters only grow.
struct NCLINK_API ClientStats {
    std::uint64_t requests = 0;             ///< requests published
    std::uint64_t responses = 0;            ///< responses matched to a pending request
    std::uint64_t timeouts = 0;             ///< requests completed with ErrorCode::timeout
    std::uint64_t late_responses = 0;       ///< responses for a request that had already timed out (dropped)
    std::uint64_t unmatched_responses = 0;  ///< responses whose @id is unknown or of another kind (dropped)
    std::uint64_t malformed = 0;            ///< messages that could not be decoded (dropped)
    std::uint64_t unreachable = 0;          ///< requests completed by a DEV_UNREACHABLE answer
    std::uint64_t samples = 0;              ///< Sample DTUs handed to handlers
    std::uint64_t notifications = 0;        ///< state, version and method-run (subscribe_method_runs) DTUs handed to handlers
    std::uint64_t queued = 0;               ///< requests made while disconnected (held, sent on reconnect)
    std::uint64_t events = 0;               ///< Event DTUs handed to event callbacks and subscribe_events handlers
    std::uint64_t duplicates = 0;           ///< Sample/Event DTUs received again and not handed on (QoS 1 repeats)
    std::uint64_t keepalives = 0;           ///< liveness Queries sent (ClientOptions::keepalive_interval)
    std::uint64_t resent = 0;               ///< queued requests sent again when their device announced itself (8.3.6)
    TransportStats transport;               ///< the broker connection (last_error: why it does not connect)
};

using SubscriptionId = std::uint64_t;

/// A Method/Status (8.2.23) or Method/Result (8.2.24) DTU of a method call
/// at a device, whichever application made the call (subscribe_method_runs).
/// The status's and the result's `msg_id` is the call's @id, `id` the method.
struct NCLINK_API MethodRun {
    enum class Kind { status, result };
    Kind kind = Kind::status;
    std::string dev;                     ///< the adapter (the topic's {dev})
    std::string ex;                      ///< the calling application (the topic's last level; "" when absent)
    std::optional<MethodStatus> status;  ///< set when kind is status
    std::optional<MethodResult> result;  ///< set when kind is result
};

/// "status", "result".
NCLINK_API std::string_view to_string(MethodRun::Kind kind) noexcept;

/// An Event DTU (8.2.31) of any application's registration at a device
/// (subscribe_events).
struct NCLINK_API WatchedEvent {
    std::string dev;  ///< the adapter (the topic's {dev})
    std::string ex;   ///< the application that registered the event (the topic's last level)
    EventData event;
};

/// Handlers of subscriptions; run on the dispatch thread.
using SampleHandler = std::function<void(const SampleDtu&)>;
using StateHandler = std::function<void(const NotifyState&)>;
using VersionHandler = std::function<void(const ProbeVersionRequest&)>;
using MethodRunHandler = std::function<void(const MethodRun&)>;
using WatchedEventHandler = std::function<void(const WatchedEvent&)>;

template <class T>
using Completion = std::function<void(Result<T>)>;

class NCLINK_API Client {
public:
    /// A client over `transport` (not yet started; the client sets its handlers).
    /// Fails with parameter_missing when ex_cid is empty or transport is null.
    static Result<std::unique_ptr<Client>> create(std::unique_ptr<Transport> transport, ClientOptions options);
    /// A client over MQTT; an empty mqtt.client_id becomes ex_cid. For a
    /// persistent session (what the adapter publishes at QoS 1 while the
    /// application is away is queued by the broker and delivered when it
    /// connects again) set mqtt.clean_session = false and keep the client id
    /// the same from run to run (docs/delivery.md).
    static Result<std::unique_ptr<Client>> create(MqttOptions mqtt, ClientOptions options);

    ~Client();  ///< stop()s
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    /// Subscribes to this client's response topics, starts the dispatch thread
    /// and the transport (which connects in the background). Once only.
    Result<void> start();
    /// Blocks until the link is up (true) or `timeout` passes (false).
    bool wait_connected(std::chrono::milliseconds timeout);
    /// start() (if not yet), wait_connected(), then register_terminal(). Fails
    /// with timeout when the link does not come up; no agent answering the
    /// registration is the outcome no_answer, not a failure.
    Result<RegisterOutcome> connect(std::chrono::milliseconds timeout);
    /// Completes every pending request with unavailable, stops the transport and
    /// joins the dispatch thread. Idempotent; not from a callback.
    void stop();

    // ---- requests, asynchronous: `done` runs once, on the dispatch thread ----
    /// Register/Request {cli_uuid: ex_cid}, answered on Register/Response/{ex_cid}.
    void register_async(Completion<RegisterOutcome> done, RequestOptions options = {});
    /// Probe/Query: the model as a JSON object.
    void probe_async(const std::string& dev, Completion<Json> done, RequestOptions options = {});
    /// Probe/Set: replaces the device's model.
    void probe_set_async(const std::string& dev, Json model, Completion<void> done, RequestOptions options = {});
    /// Query: one result per item, in order (OK with `values`, or NG with reason/error).
    void query_async(const std::string& dev, std::vector<QueryItem> items, Completion<std::vector<QueryResult>> done,
                     RequestOptions options = {});
    /// Set: one result per item, in order.
    void set_async(const std::string& dev, std::vector<SetItem> items, Completion<std::vector<SetResult>> done,
                   RequestOptions options = {});

    /// Discovery/Request: the adapters this application may access, as the
    /// agent lists them (guid, status, lastAliveTimeStamp). An empty list when
    /// the agent answers deviceList null; 203 when no agent answers.
    void discover_async(Completion<std::vector<DeviceListEntry>> done, RequestOptions options = {});

    // ---- the same, blocking (not from a callback) ------------------------------
    Result<RegisterOutcome> register_terminal(RequestOptions options = {});
    Result<std::vector<DeviceListEntry>> discover(RequestOptions options = {});
    Result<Json> probe(const std::string& dev, RequestOptions options = {});
    Result<void> probe_set(const std::string& dev, Json model, RequestOptions options = {});
    Result<std::vector<QueryResult>> query(const std::string& dev, std::vector<QueryItem> items, RequestOptions options = {});
    Result<std::vector<SetResult>> set(const std::string& dev, std::vector<SetItem> items, RequestOptions options = {});

    // ---- subscriptions ----------------------------------------------------------
    /// Sample DTUs of the model channels, `Sample/{dev}/+` (or one channel).
    Result<SubscriptionId> subscribe_samples(const std::string& dev, SampleHandler handler,
                                             std::optional<std::string> channel = std::nullopt);
    /// `Notify/State/{tid}`. The state is retained, so the current one arrives
    /// right after subscribing (and again after every reconnect).
    Result<SubscriptionId> subscribe_state(const std::string& tid, StateHandler handler);
    /// `Notify/State/+`: the states of every terminal (adapters, and the
    /// applications an agent announces), each retained one right after
    /// subscribing. NotifyState::tid names the terminal. For applications that
    /// follow whatever adapters exist without an agent (docs/bridge.md).
    Result<SubscriptionId> subscribe_all_states(StateHandler handler);
    /// `Probe/Version/{dev}`: the adapter announces its model version.
    Result<SubscriptionId> subscribe_version(const std::string& dev, VersionHandler handler);
    /// Method runs at `dev` of every application, not only this one's:
    /// `Method/Status/{dev}/+` and `Method/Result/{dev}/+` (8.2.23, 8.2.24),
    /// each DTU decoded and handed on as a MethodRun naming the caller (`ex`)
    /// and the kind. For watching (a dashboard): this client's own calls
    /// still answer call_method_async as before, and show up here too. A
    /// DTU that does not decode is counted in ClientStats::malformed and
    /// dropped; a repeated Method/Result of one call is handed on once.
    /// On a broker with the agent's ACL this needs the `watch` right
    /// (docs/security.md); without it the broker delivers only this
    /// application's own. Handlers run on the dispatch thread.
    Result<SubscriptionId> subscribe_method_runs(const std::string& dev, MethodRunHandler handler);
    /// Event DTUs (8.2.31) at `dev` of every application's registrations:
    /// `Event/{dev}/+`, decoded, handed on as a WatchedEvent naming the
    /// registering application (`ex`), each once (by @id, as for
    /// register_event). This client's own registrations still call their
    /// register_event callbacks. Malformed DTUs are counted and dropped.
    /// Needs the `watch` right like subscribe_method_runs. Handlers run on
    /// the dispatch thread.
    Result<SubscriptionId> subscribe_events(const std::string& dev, WatchedEventHandler handler);
    /// Removes a subscription (the broker subscription goes with the last
    /// handler of its filter). Called on the dispatch thread it takes effect at
    /// once; from another thread a handler call already under way may finish.
    Result<void> unsubscribe(SubscriptionId id);

    // ==== methods (8.2.22-8.2.26; src/client/client_methods.cpp, docs/methods.md) ====
    /// Method/Control actions (8.2.25): stop pauses, resume continues, cancel ends.
    enum class MethodAction { stop, resume, cancel };
    /// "stop", "resume", "cancel".
    static std::string_view method_action_name(MethodAction action) noexcept;

    /// Method/Call of the METHOD `method_id` with `args` (a JSON object; null =
    /// none). `on_status` (may be empty) gets each Method/Status of this call
    /// (status waiting/executing/stopped/sleep, progress percent, `msg_id` = the
    /// call's @id); `done` gets its Method/Result, whatever `result` says
    /// (finished, canceled, or error: a refused call, e.g. 401/102/409/417,
    /// is an error result with code NG and the table-19 reason/error). Both
    /// run on the dispatch thread; every on_status comes before done. `done`
    /// gets an Error only when no Method/Result came: 203 when neither a
    /// Status nor the Result arrived for the request timeout (each Status
    /// restarts it, so a long method keeps its call alive: keep the timeout
    /// above the adapter's methods.status_period), 202 when the client stopped
    /// or the agent answered DEV_UNREACHABLE. Thread-safe.
    void call_method_async(const std::string& dev, const std::string& method_id, Json args,
                           std::function<void(const MethodStatus&)> on_status, Completion<MethodResult> done,
                           RequestOptions options = {});
    /// Blocking form (not from a callback); on_status still runs on the dispatch thread.
    Result<MethodResult> call_method(const std::string& dev, const std::string& method_id, Json args,
                                     std::function<void(const MethodStatus&)> on_status = {}, RequestOptions options = {});
    /// Method/Control on the running calls of `method_id` at `dev`: this
    /// application's own calls, else (as an operator) everybody's;
    /// options.private_info = {"call": <the call's @id>} narrows it to one
    /// call. OK completes with success; NG with the Error of its code (401
    /// unknown method, 418 bad action, 202 not running). Thread-safe.
    void control_method_async(const std::string& dev, const std::string& method_id, MethodAction action, Completion<void> done,
                              RequestOptions options = {});
    Result<void> control_method(const std::string& dev, const std::string& method_id, MethodAction action,
                                RequestOptions options = {});
    // ==== end of methods ==============================================================

    // ==== dynamic sampling (8.2.17-8.2.21; src/client/client_sampling.cpp, docs/dynamic-sampling.md) ====
    /// A dynamic sample channel this application registered.
    struct SamplingChannel {
        std::string dev;
        std::string id;                   ///< the channel id the adapter allocated ("dyn<n>")
        SubscriptionId subscription = 0;  ///< the handler's subscription (unregister_sampling removes it)
    };
    /// Register/Sample: asks `dev` to read `ids` every `sample_interval` and
    /// publish them every `upload_interval` on Sample/{dev}/{ex_cid}/{channel}.
    /// `handler` is subscribed before the request goes out and gets the DTUs
    /// of the allocated channel only, on the dispatch thread. `done` gets the
    /// channel, or the Error of the adapter's NG (401 unknown id, 411 bad
    /// intervals, 415 no dynamic channel left, ...); on any failure the
    /// handler's subscription is removed again. options.private_info
    /// {"qos": 0} asks for QoS 0 Sample DTUs (default QoS 1). The adapter
    /// releases the channel when this application sends it no DTU for its
    /// application lease (the client's keep-alive prevents that while the
    /// client runs), or goes offline. Thread-safe.
    void register_sampling_async(const std::string& dev, std::vector<std::string> ids, std::chrono::milliseconds sample_interval,
                                 std::chrono::milliseconds upload_interval, SampleHandler handler,
                                 Completion<SamplingChannel> done, RequestOptions options = {});
    /// Blocking form (not from a callback).
    Result<SamplingChannel> register_sampling(const std::string& dev, std::vector<std::string> ids,
                                              std::chrono::milliseconds sample_interval, std::chrono::milliseconds upload_interval,
                                              SampleHandler handler, RequestOptions options = {});
    /// Unregister/Sample of `channel`; its handler subscription goes too, also
    /// when the adapter refuses (401 unknown channel, 301 not this
    /// application's). Thread-safe.
    void unregister_sampling_async(const SamplingChannel& channel, Completion<void> done, RequestOptions options = {});
    Result<void> unregister_sampling(const SamplingChannel& channel, RequestOptions options = {});
    /// True for a Sample DTU the adapter held while the broker was unreachable
    /// and replayed later: privateInfo {"replayed": true} (docs/store-and-forward.md).
    static bool is_replayed(const SampleDtu& dtu) noexcept;
    // ==== end of dynamic sampling =====================================================

    // ==== events (8.2.27-8.2.31; src/client/client_events.cpp, docs/events.md) ====
    /// What a Register/Event asks for (table 48).
    struct EventRegistration {
        std::string id;                     ///< the data item
        std::optional<std::string> key;     ///< a dict item's element (required for dicts)
        std::optional<std::int64_t> index;  ///< a list item's element (required for lists)
        /// Figure-16 filter objects, OR-ed in order, e.g. {"type":"range","from":10,"to":20};
        /// empty = the adapter's default change filter.
        std::vector<Json> filters;
        std::string trigger = "always";  ///< triggerType: always | normal | once
    };
    /// Gets the Event DTUs of one registration (8.2.31), on the dispatch thread.
    using EventHandler = std::function<void(const EventData&)>;

    /// Register/Event at `dev`. `done` gets the adapter's event id (or the
    /// Error of its NG: 401, 402, 403, 409, 410, 101, 416, 419, 420, 421...).
    /// From the OK on, `on_event` gets every Event of the registration,
    /// including the one the adapter sends at once when the current value
    /// already matches (it arrives after `done`). A once registration's
    /// callback goes with its first event. Both callbacks run on the dispatch
    /// thread. Thread-safe. The adapter releases the events of an application
    /// it has not heard from for its application lease; the client's
    /// keep-alive (ClientOptions::keepalive_interval) keeps them while the
    /// client runs (docs/events.md, docs/delivery.md).
    void register_event_async(const std::string& dev, EventRegistration registration, EventHandler on_event,
                              Completion<std::string> done, RequestOptions options = {});
    /// Blocking form (not from a callback): the event id.
    Result<std::string> register_event(const std::string& dev, EventRegistration registration, EventHandler on_event,
                                       RequestOptions options = {});
    /// Unregister/Event. The callback is dropped at once (no Event reaches it
    /// after this call, whatever the answer); `done` gets OK or the Error of
    /// the NG (401 unknown event, 301 another application's). Thread-safe.
    void unregister_event_async(const std::string& dev, const std::string& event_id, Completion<void> done,
                                RequestOptions options = {});
    Result<void> unregister_event(const std::string& dev, const std::string& event_id, RequestOptions options = {});
    /// Registrations whose callbacks are in place (once ones leave after firing).
    std::size_t event_registrations() const;
    // ==== end of events ===============================================================

    // ==== model cache (8.2.5.3, 8.2.7.3, 8.3.6; src/client/client_model_cache.cpp, docs/client.md) ====
    /// Gets each model the cache fetched for a followed device (dispatch thread).
    using ModelHandler = std::function<void(const std::string& dev, const Json& model)>;
    /// Follows `dev`'s model: probes it now, and again whenever the adapter
    /// announces (Probe/Version) a version other than the cached one (8.2.7.3:
    /// "the version differs from the cached model's: fetch it again").
    /// `on_model` gets every model fetched. Idempotent per device (a second
    /// call replaces `on_model`). Thread-safe.
    Result<void> follow_model(const std::string& dev, ModelHandler on_model = {});
    /// The cached model of a followed device (nullopt: not fetched yet).
    std::optional<Json> cached_model(const std::string& dev) const;
    /// Its version ("" when none is cached).
    std::string cached_model_version(const std::string& dev) const;
    /// Probes made because a version changed, and registrations made again
    /// after an adapter restart (see register_event/register_sampling).
    std::uint64_t model_reprobes() const;
    std::uint64_t reregistrations() const;
    // Event registrations and dynamic sample channels this client makes are
    // standing: when their adapter goes offline and then announces its
    // version again (a restart, or a reconnection: 8.3.6), the client sends
    // Unregister for the old id (401 after a restart: nothing to remove) and
    // registers again with the same callback, without the application doing
    // anything. The ids the application got keep working in
    // unregister_event()/unregister_sampling(). A registration the adapter
    // refuses when made again (its item gone from the model: 401) is dropped.
    // ==== end of model cache ==========================================================

    // ---- introspection -----------------------------------------------------------
    const std::string& ex_cid() const noexcept;
    LinkState link_state() const;
    ClientState state() const;
    ClientStats stats() const;
    std::size_t pending_requests() const;
    /// The transport (for its stats); owned by the client.
    const Transport& transport() const noexcept;

    struct Impl;

private:
    explicit Client(std::shared_ptr<Impl> impl);
    std::shared_ptr<Impl> impl_;
};

}  // namespace nclink
