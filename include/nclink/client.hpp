// The application side of NC-Link (an "application system" in GB/T 41970-2022):
// register with the agent, probe, query and set a device's data items, and
// receive samples, state and version notifications.
//
// Thread contract (see docs/client.md):
// - Every public member function is thread-safe and may be called from any
//   thread, concurrently.
// - Every callback (request completions, sample/state/version handlers, the
//   link-state handler) runs on the client's own dispatch thread, one at a
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

#include <nclink/dtu.hpp>
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

/// The application state of seed 004 (initial, normal, request, disconnected).
/// For now derived from the link and the pending requests; the full state
/// machine (queueing requests while disconnected, replaying them on
/// reconnect) comes later. Until then requests made while the link is down
/// wait in the transport's offline buffer, their timeouts running.
enum class ClientState {
    initial,       ///< not started, or the link has never come up
    normal,        ///< connected, no request outstanding
    request,       ///< connected, at least one request waiting for its response
    disconnected,  ///< the link was up and is down now
};

std::string_view to_string(ClientState state) noexcept;

struct ClientOptions {
    /// The application's terminal id (ex_cid): cli_uuid when registering and the
    /// last level of every request topic (responses mirror it). Required.
    std::string ex_cid;
    /// Timeout of a request whose RequestOptions give none.
    std::chrono::milliseconds default_timeout{2000};
    /// How long stop() lets the transport flush what is still buffered.
    std::chrono::milliseconds stop_flush_timeout{500};
    /// Called on the dispatch thread when the link changes state.
    std::function<void(LinkState)> on_link_state;
    Logger logger;
};

struct RequestOptions {
    std::optional<std::chrono::milliseconds> timeout;  ///< default: ClientOptions::default_timeout
    std::optional<Json> private_info;                   ///< sent as "privateInfo"
};

/// What came of Register/Request. Registration is an agent feature: without an
/// agent (adapter and application on a bare broker) nobody answers, and the
/// application goes on working, so no answer is an outcome, not an error.
struct RegisterOutcome {
    enum class Kind { accepted, refused, no_answer };
    Kind kind = Kind::no_answer;
    ResponseStatus status;  ///< the agent's code/reason/error (accepted/refused)
};

std::string_view to_string(RegisterOutcome::Kind kind) noexcept;

/// Counters only grow.
struct ClientStats {
    std::uint64_t requests = 0;             ///< requests published
    std::uint64_t responses = 0;            ///< responses matched to a pending request
    std::uint64_t timeouts = 0;             ///< requests completed with ErrorCode::timeout
    std::uint64_t late_responses = 0;       ///< responses for a request that had already timed out (dropped)
    std::uint64_t unmatched_responses = 0;  ///< responses whose @id is unknown or of another kind (dropped)
    std::uint64_t malformed = 0;            ///< messages that could not be decoded (dropped)
    std::uint64_t unreachable = 0;          ///< requests completed by a DEV_UNREACHABLE answer
    std::uint64_t samples = 0;              ///< Sample DTUs handed to handlers
    std::uint64_t notifications = 0;        ///< state and version notifications handed to handlers
};

using SubscriptionId = std::uint64_t;

/// Handlers of subscriptions; run on the dispatch thread.
using SampleHandler = std::function<void(const SampleDtu&)>;
using StateHandler = std::function<void(const NotifyState&)>;
using VersionHandler = std::function<void(const ProbeVersionRequest&)>;

template <class T>
using Completion = std::function<void(Result<T>)>;

class Client {
public:
    /// A client over `transport` (not yet started; the client sets its handlers).
    /// Fails with parameter_missing when ex_cid is empty or transport is null.
    static Result<std::unique_ptr<Client>> create(std::unique_ptr<Transport> transport, ClientOptions options);
    /// A client over MQTT; an empty mqtt.client_id becomes ex_cid.
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

    // ---- the same, blocking (not from a callback) ------------------------------
    Result<RegisterOutcome> register_terminal(RequestOptions options = {});
    Result<Json> probe(const std::string& dev, RequestOptions options = {});
    Result<void> probe_set(const std::string& dev, Json model, RequestOptions options = {});
    Result<std::vector<QueryResult>> query(const std::string& dev, std::vector<QueryItem> items,
                                           RequestOptions options = {});
    Result<std::vector<SetResult>> set(const std::string& dev, std::vector<SetItem> items,
                                       RequestOptions options = {});

    // ---- subscriptions ----------------------------------------------------------
    /// Sample DTUs of the model channels, `Sample/{dev}/+` (or one channel).
    Result<SubscriptionId> subscribe_samples(const std::string& dev, SampleHandler handler,
                                             std::optional<std::string> channel = std::nullopt);
    /// `Notify/State/{tid}`. The state is retained, so the current one arrives
    /// right after subscribing (and again after every reconnect).
    Result<SubscriptionId> subscribe_state(const std::string& tid, StateHandler handler);
    /// `Probe/Version/{dev}`: the adapter announces its model version.
    Result<SubscriptionId> subscribe_version(const std::string& dev, VersionHandler handler);
    /// Removes a subscription (the broker subscription goes with the last
    /// handler of its filter). Called on the dispatch thread it takes effect at
    /// once; from another thread a handler call already under way may finish.
    Result<void> unsubscribe(SubscriptionId id);

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
