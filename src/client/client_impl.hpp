// The client's insides, shared by the files that implement it:
//   client.cpp           the public facade: create, lifecycle, the core
//                        requests (register, discovery, probe, query, set),
//                        subscriptions, statistics
//   client_impl.cpp      the engine: the lifecycle, transport callbacks
//                        handed to the dispatch thread, deadlines
//   client_liveness.cpp  keep-alive Queries (3.22)
//   client_model_cache.cpp the model cache and standing registrations
//   client_methods.cpp, client_sampling.cpp, client_events.cpp: one feature each
// and the objects it composes, each owning its state and lock: ClientLink
// (the transport, the link's state, the subscriptions), PendingRequests and
// ClientStateMachine (the send path), Dispatcher (the dispatch thread),
// MessageRouter (every DTU in: responses by @id, subscriptions, repeats
// dropped, the last Notify/State per terminal), ModelCacheState,
// EventRoutes, KeepAlive.
// Nothing outside src/client/ includes this.
#pragma once

#include "client/client_link.hpp"
#include "client/client_state_machine.hpp"
#include "client/dispatcher.hpp"
#include "client/pending_requests.hpp"
#include "client/request_ids.hpp"
#include "client/responders.hpp"
#include "client/client_events.hpp"
#include "client/client_model_cache.hpp"
#include "client/keep_alive.hpp"
#include "client/message_router.hpp"
#include "client/safely.hpp"

#include <nclink/client.hpp>
#include <nclink/topics.hpp>

#include <atomic>
#include <exception>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace nclink {

struct NCLINK_LOCAL Client::Impl {
    using Clock = client_detail::Clock;

    ClientOptions options;
    Logger log;
    client_detail::ClientLink link;  // the transport, the link's state, the subscriptions
    client_detail::RequestIds ids;
    client_detail::PendingRequests pending;
    client_detail::ClientCounters counters;
    std::mutex lifecycle_mutex;
    bool started = false;
    bool stopped = false;
    client_detail::ClientStateMachine machine;   // docs/state-machines.md; the send path goes through it
    client_detail::EventRoutes event_routes;     // client_events.cpp
    client_detail::ModelCacheState model_cache;  // client_model_cache.cpp
    Client* owner = nullptr;                     // the facade, for the cache's own requests (set once, by Client's constructor)
    client_detail::KeepAlive keep_alive;         // client_liveness.cpp
    client_detail::MessageRouter router;         // every DTU in (dispatch thread)
    client_detail::Dispatcher dispatcher;        // last: its thread uses everything above

    Impl(std::unique_ptr<Transport> t, ClientOptions o)
        : options(std::move(o)),
          log(options.logger),
          link(std::move(t)),
          ids(options.ex_cid),
          machine(client_detail::ClientStateMachine::Hooks{
                      [this](const std::string& id) { return (pending.peek(id, nullptr) != nullptr); },
                      [this] { return pending.size() > 0; }, [this](Message m) { return link.transport().publish(std::move(m)); }},
                  options.max_queued_requests),
          keep_alive(options.keepalive_interval),
          router(client_detail::MessageRouter::Parts{options.ex_cid, log, counters, link, pending, event_routes,
                                                     [this](const std::string& dev, const std::string& payload) {
                                                         note_instance(dev, payload);
                                                     }},
                 options.duplicate_memory),
          dispatcher(client_detail::Dispatcher::Hooks{
              [this] { return next_wake(); },
              [this](Clock::time_point now) {
                  expire(now);
                  send_keepalives(now);
              },
              [this] { fail_all(); },
              [this](const char* what) { log.error("client: a callback threw: {}", what); },
          }) {}

    Result<void> start();

    void stop();

    // ---- transport callback thread: copy and hand over, never block ----
    void on_message(const Message& m);

    void on_link(LinkState state, std::string_view detail);

    // ---- dispatch thread ----
    void expire(Clock::time_point now);

    // ---- liveness (client_liveness.cpp) ----
    std::optional<Clock::time_point> next_wake() const;
    void send_keepalives(Clock::time_point now);  ///< dispatch thread

    void fail_all();

    // ---- requests (any thread) ----
    template <class Request>
    void send(TopicKind response_kind, std::string topic, Request request, std::shared_ptr<client_detail::Responder> responder,
              const RequestOptions& request_options) {
        if (!dispatcher.running()) {
            client_detail::safely(log, [&] { responder->fail(make_error(ErrorCode::unavailable, "client is not running")); });
            return;
        }
        std::string id = ids.next();
        request.msg_id = Json(id);
        if (request_options.private_info) request.private_info = request_options.private_info;
        const auto timeout = request_options.timeout.value_or(options.default_timeout);
        const auto parsed_topic = parse_topic(topic);
        const std::string dev = parsed_topic ? parsed_topic->dev : std::string();
        if (!pending.add(client_detail::PendingRequest{id, response_kind, Clock::now() + timeout, responder, dev})) {
            client_detail::safely(log, [&] { responder->fail(make_error(ErrorCode::unavailable, "client stopped")); });
            return;
        }
        dispatcher.poke();  // its deadline may be the nearest now
        // A request made while the link is down goes out when it returns,
        // perhaps before its adapter subscribed again: its device's
        // Probe/Version is then what says to send it again (8.3.6,
        // ClientStateMachine::resend). Subscribed before it is queued, so the
        // subscription is on the broker before the queue goes out.
        if (!dev.empty() && dev != options.ex_cid && !link.connected())
            (void)watch_device(dev);  // (Discovery's topic level is the application itself)
        auto submitted = machine.submit(id, dev, Message{std::move(topic), encode(request), 1, false}, [&] {
            return pending.add(
                client_detail::PendingRequest{id, response_kind, Clock::now() + timeout,
                                              client_detail::track_completion(responder, [this] { machine.completed(); }), dev});
        });
        if (submitted) {
            ++(*submitted == client_detail::ClientStateMachine::Outcome::queued ? counters.queued : counters.requests);
            return;
        }
        if (!(pending.peek(id, nullptr) != nullptr)) {  // never entered: the client is stopping, or the queue is full
            client_detail::safely(log, [&] { responder->fail(std::move(submitted).error()); });
            return;
        }
        fail_request(id, std::move(submitted).error());
    }

    // ---- model cache and standing registrations (client_model_cache.cpp) ----
    /// Records a registration being made (unless the cache itself makes it
    /// again); returns `done` wrapped to note the id the adapter gives.
    Completion<std::string> stand_event(const std::string& dev, const Client::EventRegistration& registration,
                                        const Client::EventHandler& handler, const RequestOptions& request_options,
                                        Completion<std::string> done);
    Completion<Client::SamplingChannel> stand_channel(const std::string& dev, const std::vector<std::string>& item_ids,
                                                      std::chrono::milliseconds sample_interval,
                                                      std::chrono::milliseconds upload_interval, const SampleHandler& handler,
                                                      const RequestOptions& request_options,
                                                      Completion<Client::SamplingChannel> done);
    /// The application unregisters: forgets the record; returns the id (or
    /// channel) the adapter knows now.
    std::string unstand_event(const std::string& dev, const std::string& event_id);
    Client::SamplingChannel unstand_channel(const Client::SamplingChannel& channel);
    /// Subscribes the device's Notify/State and Probe/Version once.
    Result<void> watch_device(const std::string& dev);
    void on_device_version(const std::string& dev, const ProbeVersionRequest& version);  ///< dispatch thread
    void on_device_state(const std::string& dev, const NotifyState& state);              ///< dispatch thread
    /// Records the adapter run a registration answer names (privateInfo.instance); dispatch thread.
    void note_instance(const std::string& dev, const std::string& payload);
    void reprobe(const std::string& dev);
    void reregister(const std::string& dev);

    // Fails a pending request whose publish failed; on the dispatch thread when it runs.
    void fail_request(const std::string& id, Error error);
};

}  // namespace nclink
