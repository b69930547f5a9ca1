// The client's insides, shared by the files that implement it:
//   client.cpp           the public facade: create, lifecycle, the core
//                        requests (register, discovery, probe, query, set),
//                        subscriptions, statistics
//   client_impl.cpp      the engine: transport callbacks handed to the
//                        dispatch thread, response matching by @id,
//                        notifications, deadlines
//   client_methods.cpp, client_sampling.cpp, client_events.cpp: one feature each
// Nothing outside src/client/ includes this.
#pragma once

#include "client/client_state_machine.hpp"
#include "client/dispatcher.hpp"
#include "client/pending_requests.hpp"
#include "client/request_ids.hpp"
#include "client/responders.hpp"
#include "client/subscriptions.hpp"
#include "client/client_events.hpp"

#include <nclink/client.hpp>
#include <nclink/topics.hpp>

#include <atomic>
#include <condition_variable>
#include <exception>
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
        std::atomic<std::uint64_t> requests{0}, responses{0}, timeouts{0}, late{0}, unmatched{0}, malformed{0},
            unreachable{0}, samples{0}, notifications{0}, queued{0}, events{0};
    };

    ClientOptions options;
    Logger log;
    std::unique_ptr<Transport> transport;
    client_detail::RequestIds ids;
    client_detail::PendingRequests pending;
    client_detail::SubscriptionRegistry subscriptions;
    Counters counters;
    std::mutex lifecycle_mutex;
    bool started = false;
    bool stopped = false;
    std::mutex subscribe_mutex;  // keeps registry and broker subscriptions in step
    std::mutex link_mutex;
    std::condition_variable link_changed;
    LinkState link = LinkState::disconnected;
    bool ever_connected = false;
    client_detail::ClientStateMachine machine;  // docs/state-machines.md; the send path goes through it
    client_detail::EventRoutes event_routes;  // client_events.cpp
    client_detail::Dispatcher dispatcher;  // last: its thread uses everything above

    Impl(std::unique_ptr<Transport> t, ClientOptions o)
        : options(std::move(o)),
          log(options.logger),
          transport(std::move(t)),
          ids(options.ex_cid),
          machine(client_detail::ClientStateMachine::Hooks{
                      [this](const std::string& id) { return (pending.peek(id, nullptr) != nullptr); },
                      [this] { return pending.size() > 0; },
                      [this](Message m) { return transport->publish(std::move(m)); }},
                  options.max_queued_requests),
          dispatcher(client_detail::Dispatcher::Hooks{
              [this] { return pending.next_deadline(); },
              [this](Clock::time_point now) { expire(now); },
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
        if (!pending.add(client_detail::PendingRequest{id, response_kind, Clock::now() + timeout, responder})) {
            client_detail::safely(log, [&] { responder->fail(make_error(ErrorCode::unavailable, "client stopped")); });
            return;
        }
        dispatcher.poke();  // its deadline may be the nearest now
        auto submitted = machine.submit(id, Message{std::move(topic), encode(request), 1, false}, [&] {
            return pending.add(client_detail::PendingRequest{id, response_kind, Clock::now() + timeout,
                                              client_detail::track_completion(responder, [this] { machine.completed(); })});
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

    // Fails a pending request whose publish failed; on the dispatch thread when it runs.
    void fail_request(const std::string& id, Error error);


    Result<SubscriptionId> subscribe(std::string filter, client_detail::AnyHandler handler) {
        std::lock_guard<std::mutex> lock(subscribe_mutex);
        auto sub = subscriptions.add(filter, std::move(handler));
        // Subscribing again even when the filter is known: the broker then
        // re-sends retained messages (the current state) for the new handler.
        if (auto r = transport->subscribe({std::move(filter)}, 1); !r) {
            bool found = false;
            (void)subscriptions.remove(sub->id, found);
            return std::move(r).error();
        }
        return sub->id;
    }
};


}  // namespace nclink
