// The client's insides, shared by the files that implement it:
//   client.cpp           the public facade: create, lifecycle, the core
//                        requests (register, discovery, probe, query, set),
//                        subscriptions, statistics
//   client_impl.cpp      the engine: transport callbacks handed to the
//                        dispatch thread, response matching by @id,
//                        notifications, deadlines
//   client_methods.cpp, client_sampling.cpp, client_events.cpp: one feature each
// and the objects it composes, each owning its state and lock: ClientLink
// (the transport, the link's state, the subscriptions), PendingRequests and
// ClientStateMachine (the send path), Dispatcher (the dispatch thread),
// ModelCacheState, EventRoutes, KeepAlive, DuplicateFilter.
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
#include "client/duplicate_filter.hpp"
#include "client/keep_alive.hpp"

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

namespace client_detail {

/// Runs a user callback; what it throws is logged, never propagated into
/// the client's threads.
template <class F>
void safely(const Logger& log, F&& f) noexcept {
    try {
        f();
    } catch (const std::exception& e) {
        log.error("client: a callback threw: {}", e.what());
    } catch (...) {
        log.error("client: a callback threw");
    }
}

}  // namespace client_detail

struct NCLINK_LOCAL Client::Impl {
    using Clock = client_detail::Clock;
    struct Counters {
        std::atomic<std::uint64_t> requests{0}, responses{0}, timeouts{0}, late{0}, unmatched{0}, malformed{0}, unreachable{0},
            samples{0}, notifications{0}, queued{0}, events{0}, duplicates{0}, keepalives{0}, resent{0};
    };

    ClientOptions options;
    Logger log;
    client_detail::ClientLink link;  // the transport, the link's state, the subscriptions
    client_detail::RequestIds ids;
    client_detail::PendingRequests pending;
    Counters counters;
    std::mutex lifecycle_mutex;
    bool started = false;
    bool stopped = false;
    client_detail::ClientStateMachine machine;   // docs/state-machines.md; the send path goes through it
    client_detail::EventRoutes event_routes;     // client_events.cpp
    client_detail::ModelCacheState model_cache;  // client_model_cache.cpp
    Client* owner = nullptr;                     // the facade, for the cache's own requests (set once, by Client's constructor)
    client_detail::KeepAlive keep_alive;         // client_liveness.cpp
    client_detail::DuplicateFilter duplicates;   // dispatch thread only
    // The last Notify/State seen per terminal (on the dispatch thread, from
    // any state subscription), so a request that times out can name a
    // retained "offline" (8.2.16) instead of only "no response".
    std::map<std::string, std::string> known_states;  // dispatch thread only
    client_detail::Dispatcher dispatcher;             // last: its thread uses everything above

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
          duplicates(options.duplicate_memory),
          dispatcher(client_detail::Dispatcher::Hooks{
              [this] { return next_wake(); },
              [this](Clock::time_point now) {
                  expire(now);
                  send_keepalives(now);
              },
              [this] { fail_all(); },
              [this](const char* what) { log.error("client: a callback threw: {}", what); },
          }) {}

    std::vector<std::string> response_filters() const;

    Result<void> start();

    void stop();

    // ---- transport callback thread: copy and hand over, never block ----
    void on_message(const Message& m);

    void on_link(LinkState state, std::string_view detail);

    // ---- dispatch thread ----
    void handle_message(const Message& m);

    void handle_response(const ParsedTopic& topic, const std::string& payload);

    void handle_notification(const ParsedTopic& topic, const Message& m);

    /// Event/{dev}/{ex}: this client's own go to their registrations
    /// (client_events.cpp), every one to subscribe_events() handlers.
    void handle_event(const ParsedTopic& topic, const Message& m);

    /// Method/Status and Method/Result/{dev}/{ex}: this client's own go to
    /// their calls (client_methods.cpp), every one to subscribe_method_runs() handlers.
    void handle_method_run(const ParsedTopic& topic, const Message& m);

    template <class Handler, class Dtu>
    void deliver_to(const std::vector<std::shared_ptr<client_detail::Subscription>>& subs, const Dtu& dtu,
                    std::atomic<std::uint64_t>& counter) {
        for (const auto& sub : subs) {
            const auto* handler = std::get_if<Handler>(&sub->handler);
            if (!handler || !*handler || !sub->alive) continue;
            ++counter;
            client_detail::safely(log, [&] { (*handler)(dtu); });
        }
    }

    void expire(Clock::time_point now);

    // ---- liveness and de-duplication (client_liveness.cpp) ----
    std::optional<Clock::time_point> next_wake() const;
    void send_keepalives(Clock::time_point now);  ///< dispatch thread
    /// False for a Sample/Event DTU already handed on (counted): Samples by
    /// topic and beginTime, Events by device and @id.
    bool first_delivery(const std::string& stream, const std::string& key);

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
