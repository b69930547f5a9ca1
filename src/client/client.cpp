// Client: wires the transport, the pending-request table, the subscription
// registry and the dispatch thread together.
#include <nclink/client.hpp>

#include "client/blocking_call.hpp"
#include "client/client_state_machine.hpp"
#include "client/discovery_responder.hpp"
#include "client/dispatcher.hpp"
#include "client/client_methods.hpp"
#include "client/client_sampling.hpp"
#include "client/client_events.hpp"
#include "client/pending_requests.hpp"
#include "client/request_ids.hpp"
#include "client/responders.hpp"
#include "client/subscriptions.hpp"

#include <nclink/topics.hpp>

#include <atomic>
#include <condition_variable>
#include <exception>
#include <future>
#include <mutex>
#include <utility>

namespace nclink {

using client_detail::Clock;
using client_detail::Dispatcher;
using client_detail::PendingRequest;
using client_detail::Responder;

std::string_view to_string(RegisterOutcome::Kind kind) noexcept {
    switch (kind) {
        case RegisterOutcome::Kind::accepted: return "accepted";
        case RegisterOutcome::Kind::refused: return "refused";
        case RegisterOutcome::Kind::no_answer: return "no answer";
    }
    return "?";
}

namespace {

// A terminal id is one topic level: no separators or wildcards.
bool valid_topic_level(std::string_view level) {
    if (level.empty()) return false;
    for (char c : level)
        if (c == '/' || c == '+' || c == '#' || c == '\0') return false;
    return true;
}

bool is_client_response(TopicKind kind) {
    switch (kind) {
        case TopicKind::register_response:
        case TopicKind::discovery_response:
        case TopicKind::probe_query_response:
        case TopicKind::probe_set_response:
        case TopicKind::query_response:
        case TopicKind::method_result:            // client_methods.cpp
        case TopicKind::method_control_response:  // client_methods.cpp
        case TopicKind::sample_register_response:    // client_sampling.cpp
        case TopicKind::sample_unregister_response:  // client_sampling.cpp
        case TopicKind::event_register_response:    // client_events.cpp
        case TopicKind::event_unregister_response:  // client_events.cpp
        case TopicKind::set_response: return true;
        default: return false;
    }
}

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

}  // namespace

struct Client::Impl {
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
    client_detail::ClientStateMachine machine;  // seed 004; the send path goes through it
    client_detail::EventRoutes event_routes;  // client_events.cpp
    Dispatcher dispatcher;  // last: its thread uses everything above

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
          dispatcher(Dispatcher::Hooks{
              [this] { return pending.next_deadline(); },
              [this](Clock::time_point now) { expire(now); },
              [this] { fail_all(); },
              [this](const char* what) { log.error("client: a callback threw: {}", what); },
          }) {}

    std::vector<std::string> response_filters() const {
        const std::string& ex = options.ex_cid;
        return {topics::register_response(ex), topics::discovery_response(ex), topics::probe_query_response("+", ex),
                topics::probe_set_response("+", ex), topics::query_response("+", ex),
                topics::set_response("+", ex),
                topics::method_result("+", ex), topics::method_status("+", ex),  // client_methods.cpp
                topics::method_control_response("+", ex),
                topics::sample_register_response("+", ex), topics::sample_unregister_response("+", ex),  // client_sampling.cpp
                topics::event_register_response("+", ex), topics::event_unregister_response("+", ex),  // client_events.cpp
                topics::event("+", ex)};
    }

    Result<void> start() {
        std::lock_guard<std::mutex> lock(lifecycle_mutex);
        if (started) return make_error(ErrorCode::unavailable, "client already started");
        started = true;
        transport->set_message_handler([this](const Message& m) { on_message(m); });
        transport->set_state_handler([this](LinkState s, std::string_view detail) { on_link(s, detail); });
        dispatcher.start();
        // Before the first request can go out: responses must find us subscribed.
        if (auto r = transport->subscribe(response_filters(), 1); !r) {
            dispatcher.stop();
            return r;
        }
        if (auto r = transport->start(); !r) {
            dispatcher.stop();
            return r;
        }
        return ok_result();
    }

    void stop() {
        if (dispatcher.on_dispatch_thread()) {
            log.error("client: stop() called from a client callback; ignored");
            return;
        }
        {
            std::lock_guard<std::mutex> lock(lifecycle_mutex);
            if (stopped) return;
            stopped = true;
            if (!started) return;
        }
        transport->stop(options.stop_flush_timeout);  // no transport callbacks after this
        dispatcher.stop();                             // runs what is queued, then fails what is pending
    }

    // ---- transport callback thread: copy and hand over, never block ----
    void on_message(const Message& m) {
        if (!dispatcher.post([this, m] { handle_message(m); }))
            log.debug("client: message on {} after stop dropped", m.topic);
    }

    void on_link(LinkState state, std::string_view detail) {
        // The state machine first: wait_connected() returns into state normal.
        if (state == LinkState::connected) {
            for (auto& [id, error] : machine.link_restored()) fail_request(id, std::move(error));
        } else if (state == LinkState::disconnected) {
            machine.link_lost();
        }
        {
            std::lock_guard<std::mutex> lock(link_mutex);
            link = state;
            if (state == LinkState::connected) ever_connected = true;
        }
        link_changed.notify_all();
        log.debug("client {}: link {} ({})", options.ex_cid, to_string(state), detail);
        if (options.on_link_state)
            dispatcher.post([this, state] { safely(log, [&] { options.on_link_state(state); }); });
    }

    // ---- dispatch thread ----
    void handle_message(const Message& m) {
        const auto parsed = parse_topic(m.topic);
        if (!parsed) {
            ++counters.unmatched;
            return;
        }
        if (parsed->kind == TopicKind::event) {  // client_events.cpp
            const auto delivery = event_routes.deliver(parsed->dev, m.payload, log);
            ++(delivery == client_detail::EventRoutes::Delivery::delivered  ? counters.events
               : delivery == client_detail::EventRoutes::Delivery::malformed ? counters.malformed
                                                                             : counters.unmatched);
            return;
        }
        if (parsed->kind == TopicKind::method_status) {
            client_detail::handle_method_status(pending, m.payload, log);  // client_methods.cpp
            return;
        }
        if (is_client_response(parsed->kind))
            handle_response(*parsed, m.payload);
        else
            handle_notification(*parsed, m);
    }

    void handle_response(const ParsedTopic& topic, const std::string& payload) {
        const MessageId msg_id = peek_message_id(payload);
        if (!msg_id) {
            ++counters.malformed;
            log.debug("client: response on {} without a usable @id dropped", build_topic(topic));
            return;
        }
        const std::string key = msg_id->is_string() ? msg_id->get<std::string>() : msg_id->dump();
        TopicKind expected = TopicKind::query_response;
        const std::shared_ptr<Responder> responder = pending.peek(key, &expected);
        if (!responder) {
            if (pending.timed_out_recently(key)) {
                ++counters.late;
                log.debug("client: late response {} dropped", key);
            } else {
                ++counters.unmatched;
            }
            return;
        }
        if (auto unreachable = client_detail::unreachable_error(payload)) {
            if (auto taken = pending.take(key)) {
                ++counters.unreachable;
                safely(log, [&] { taken->responder->fail(std::move(*unreachable)); });
            }
            return;
        }
        if (expected != topic.kind) {
            ++counters.unmatched;  // same @id on another kind of response: not ours
            return;
        }
        if (!responder->decode(payload)) {
            ++counters.malformed;
            log.warn("client: malformed response {} on {} ignored", key, build_topic(topic));
            return;
        }
        if (auto taken = pending.take(key)) {
            ++counters.responses;
            safely(log, [&] { taken->responder->complete(); });
        }
    }

    void handle_notification(const ParsedTopic& topic, const Message& m) {
        const auto subs = subscriptions.matching(m.topic);
        if (subs.empty()) return;
        switch (topic.kind) {
            case TopicKind::sample:
            case TopicKind::dynamic_sample: {  // client_sampling.cpp filters by channel
                auto dtu = decode<SampleDtu>(m.payload);
                if (!dtu) {
                    ++counters.malformed;
                    return;
                }
                if (dtu->guid.empty()) dtu->guid = topic.dev;
                deliver_to<SampleHandler>(subs, *dtu, counters.samples);
                break;
            }
            case TopicKind::notify_state: {
                if (m.payload.empty()) return;  // a cleared retained state
                auto dtu = decode<NotifyState>(m.payload);
                if (!dtu) {
                    ++counters.malformed;
                    return;
                }
                if (dtu->tid.empty()) dtu->tid = topic.dev;
                deliver_to<StateHandler>(subs, *dtu, counters.notifications);
                break;
            }
            case TopicKind::probe_version: {
                auto dtu = decode<ProbeVersionRequest>(m.payload);
                if (!dtu) {
                    ++counters.malformed;
                    return;
                }
                if (dtu->guid.empty()) dtu->guid = topic.dev;
                deliver_to<VersionHandler>(subs, *dtu, counters.notifications);
                break;
            }
            default: ++counters.unmatched; break;
        }
    }

    template <class Handler, class Dtu>
    void deliver_to(const std::vector<std::shared_ptr<client_detail::Subscription>>& subs, const Dtu& dtu,
                    std::atomic<std::uint64_t>& counter) {
        for (const auto& sub : subs) {
            const auto* handler = std::get_if<Handler>(&sub->handler);
            if (!handler || !*handler || !sub->alive) continue;
            ++counter;
            safely(log, [&] { (*handler)(dtu); });
        }
    }

    void expire(Clock::time_point now) {
        for (auto& request : pending.take_expired(now)) {
            ++counters.timeouts;
            log.debug("client: request {} timed out", request.id);
            safely(log, [&] {
                request.responder->fail(make_error(ErrorCode::timeout, "no response to " + request.id + " in time"));
            });
        }
    }

    void fail_all() {
        for (auto& request : pending.close())
            safely(log, [&] { request.responder->fail(make_error(ErrorCode::unavailable, "client stopped")); });
    }

    // ---- requests (any thread) ----
    template <class Request>
    void send(TopicKind response_kind, std::string topic, Request request, std::shared_ptr<Responder> responder,
              const RequestOptions& request_options) {
        if (!dispatcher.running()) {
            safely(log, [&] { responder->fail(make_error(ErrorCode::unavailable, "client is not running")); });
            return;
        }
        std::string id = ids.next();
        request.msg_id = Json(id);
        if (request_options.private_info) request.private_info = request_options.private_info;
        const auto timeout = request_options.timeout.value_or(options.default_timeout);
        if (!pending.add(PendingRequest{id, response_kind, Clock::now() + timeout, responder})) {
            safely(log, [&] { responder->fail(make_error(ErrorCode::unavailable, "client stopped")); });
            return;
        }
        dispatcher.poke();  // its deadline may be the nearest now
        auto submitted = machine.submit(id, Message{std::move(topic), encode(request), 1, false}, [&] {
            return pending.add(PendingRequest{id, response_kind, Clock::now() + timeout,
                                              client_detail::track_completion(responder, [this] { machine.completed(); })});
        });
        if (submitted) {
            ++(*submitted == client_detail::ClientStateMachine::Outcome::queued ? counters.queued : counters.requests);
            return;
        }
        if (!(pending.peek(id, nullptr) != nullptr)) {  // never entered: the client is stopping, or the queue is full
            safely(log, [&] { responder->fail(std::move(submitted).error()); });
            return;
        }
        fail_request(id, std::move(submitted).error());
    }

    // Fails a pending request whose publish failed; on the dispatch thread when it runs.
    void fail_request(const std::string& id, Error error) {
        if (auto taken = pending.take(id)) {
            auto task = [this, r = std::move(taken->responder), error]() mutable {
                safely(log, [&] { r->fail(std::move(error)); });
            };
            if (!dispatcher.post(task)) task();
        }
    }

    template <class T, class Start>
    Result<T> wait(Start&& start) {
        if (dispatcher.on_dispatch_thread())
            return make_error(ErrorCode::unavailable, "blocking client call from a client callback");
        auto promise = std::make_shared<std::promise<Result<T>>>();
        auto future = promise->get_future();
        start([promise](Result<T> result) { promise->set_value(std::move(result)); });
        return future.get();
    }

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

Result<std::unique_ptr<Client>> Client::create(std::unique_ptr<Transport> transport, ClientOptions options) {
    if (!transport) return make_error(ErrorCode::parameter_missing, "client: no transport");
    if (options.ex_cid.empty()) return make_error(ErrorCode::parameter_missing, "client: ex_cid is required");
    if (!valid_topic_level(options.ex_cid))
        return make_error(ErrorCode::value_type, "client: ex_cid must be one topic level (no '/', '+', '#')");
    if (options.default_timeout.count() <= 0)
        return make_error(ErrorCode::out_of_range, "client: default_timeout must be positive");
    auto impl = std::make_shared<Impl>(std::move(transport), std::move(options));
    return std::unique_ptr<Client>(new Client(std::move(impl)));
}

Result<std::unique_ptr<Client>> Client::create(MqttOptions mqtt, ClientOptions options) {
    if (mqtt.client_id.empty()) mqtt.client_id = options.ex_cid;
    auto transport = make_mqtt_transport(std::move(mqtt), options.logger);
    if (!transport) return std::move(transport).error();
    return create(std::move(transport).value(), std::move(options));
}

Client::Client(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

Client::~Client() {
    if (impl_) impl_->stop();
}

Result<void> Client::start() { return impl_->start(); }

bool Client::wait_connected(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(impl_->link_mutex);
    return impl_->link_changed.wait_for(lock, timeout, [&] { return impl_->link == LinkState::connected; });
}

Result<RegisterOutcome> Client::connect(std::chrono::milliseconds timeout) {
    bool need_start = false;
    {
        std::lock_guard<std::mutex> lock(impl_->lifecycle_mutex);
        need_start = !impl_->started;
    }
    if (need_start)
        if (auto r = start(); !r) return std::move(r).error();
    if (!wait_connected(timeout))
        return make_error(ErrorCode::timeout, "no connection to the broker within " +
                                                  std::to_string(timeout.count()) + " ms");
    return register_terminal();
}

void Client::stop() { impl_->stop(); }

void Client::register_async(Completion<RegisterOutcome> done, RequestOptions options) {
    RegisterRequest request;
    request.cli_uuid = impl_->options.ex_cid;
    impl_->send(TopicKind::register_response, topics::register_request(), std::move(request),
                client_detail::register_responder(std::move(done)), options);
}

void Client::probe_async(const std::string& dev, Completion<Json> done, RequestOptions options) {
    ProbeQueryRequest request;
    request.guid = dev;
    impl_->send(TopicKind::probe_query_response, topics::probe_query_request(dev, impl_->options.ex_cid),
                std::move(request), client_detail::probe_responder(std::move(done)), options);
}

void Client::probe_set_async(const std::string& dev, Json model, Completion<void> done, RequestOptions options) {
    ProbeSetRequest request;
    request.guid = dev;
    request.probe = std::move(model);
    impl_->send(TopicKind::probe_set_response, topics::probe_set_request(dev, impl_->options.ex_cid),
                std::move(request), client_detail::probe_set_responder(std::move(done)), options);
}

void Client::query_async(const std::string& dev, std::vector<QueryItem> items,
                         Completion<std::vector<QueryResult>> done, RequestOptions options) {
    QueryRequest request;
    request.guid = dev;
    request.ids = std::move(items);
    impl_->send(TopicKind::query_response, topics::query_request(dev, impl_->options.ex_cid), std::move(request),
                client_detail::query_responder(std::move(done)), options);
}

void Client::set_async(const std::string& dev, std::vector<SetItem> items, Completion<std::vector<SetResult>> done,
                       RequestOptions options) {
    SetRequest request;
    request.guid = dev;
    request.values = std::move(items);
    impl_->send(TopicKind::set_response, topics::set_request(dev, impl_->options.ex_cid), std::move(request),
                client_detail::set_responder(std::move(done)), options);
}

void Client::discover_async(Completion<std::vector<DeviceListEntry>> done, RequestOptions options) {
    DiscoveryRequest request;
    request.guid = impl_->options.ex_cid;
    impl_->send(TopicKind::discovery_response, topics::discovery_request(impl_->options.ex_cid), std::move(request),
                client_detail::discovery_responder(std::move(done)), options);
}

Result<std::vector<DeviceListEntry>> Client::discover(RequestOptions options) {
    return impl_->wait<std::vector<DeviceListEntry>>([&](auto done) { discover_async(std::move(done), options); });
}

Result<RegisterOutcome> Client::register_terminal(RequestOptions options) {
    return impl_->wait<RegisterOutcome>([&](auto done) { register_async(std::move(done), options); });
}

Result<Json> Client::probe(const std::string& dev, RequestOptions options) {
    return impl_->wait<Json>([&](auto done) { probe_async(dev, std::move(done), options); });
}

Result<void> Client::probe_set(const std::string& dev, Json model, RequestOptions options) {
    return impl_->wait<void>([&](auto done) { probe_set_async(dev, std::move(model), std::move(done), options); });
}

Result<std::vector<QueryResult>> Client::query(const std::string& dev, std::vector<QueryItem> items,
                                               RequestOptions options) {
    return impl_->wait<std::vector<QueryResult>>(
        [&](auto done) { query_async(dev, std::move(items), std::move(done), options); });
}

Result<std::vector<SetResult>> Client::set(const std::string& dev, std::vector<SetItem> items,
                                           RequestOptions options) {
    return impl_->wait<std::vector<SetResult>>(
        [&](auto done) { set_async(dev, std::move(items), std::move(done), options); });
}

Result<SubscriptionId> Client::subscribe_samples(const std::string& dev, SampleHandler handler,
                                                 std::optional<std::string> channel) {
    if (!valid_topic_level(dev)) return make_error(ErrorCode::value_type, "subscribe_samples: bad device id");
    if (channel && !valid_topic_level(*channel))
        return make_error(ErrorCode::value_type, "subscribe_samples: bad channel id");
    return impl_->subscribe(topics::sample(dev, channel ? std::string_view(*channel) : std::string_view("+")),
                            std::move(handler));
}

Result<SubscriptionId> Client::subscribe_state(const std::string& tid, StateHandler handler) {
    if (!valid_topic_level(tid)) return make_error(ErrorCode::value_type, "subscribe_state: bad terminal id");
    return impl_->subscribe(topics::notify_state(tid), std::move(handler));
}

Result<SubscriptionId> Client::subscribe_all_states(StateHandler handler) {
    return impl_->subscribe(topics::notify_state("+"), std::move(handler));
}

Result<SubscriptionId> Client::subscribe_version(const std::string& dev, VersionHandler handler) {
    if (!valid_topic_level(dev)) return make_error(ErrorCode::value_type, "subscribe_version: bad device id");
    return impl_->subscribe(topics::probe_version(dev), std::move(handler));
}

Result<void> Client::unsubscribe(SubscriptionId id) {
    std::lock_guard<std::mutex> lock(impl_->subscribe_mutex);
    bool found = false;
    auto last = impl_->subscriptions.remove(id, found);
    if (!found) return make_error(ErrorCode::node_not_exists, "no subscription " + std::to_string(id));
    if (last) return impl_->transport->unsubscribe({*last});
    return ok_result();
}

const std::string& Client::ex_cid() const noexcept { return impl_->options.ex_cid; }

LinkState Client::link_state() const {
    std::lock_guard<std::mutex> lock(impl_->link_mutex);
    return impl_->link;
}

ClientState Client::state() const { return impl_->machine.state(); }

ClientStats Client::stats() const {
    const auto& c = impl_->counters;
    ClientStats s;
    s.requests = c.requests;
    s.responses = c.responses;
    s.timeouts = c.timeouts;
    s.late_responses = c.late;
    s.unmatched_responses = c.unmatched;
    s.malformed = c.malformed;
    s.unreachable = c.unreachable;
    s.samples = c.samples;
    s.notifications = c.notifications;
    s.queued = c.queued;
    s.events = c.events;
    return s;
}

std::size_t Client::pending_requests() const { return impl_->pending.size(); }

const Transport& Client::transport() const noexcept { return *impl_->transport; }

// ---- the core services client_methods.cpp builds on (client_methods.hpp)
namespace client_detail {
void send_method_call(Client::Impl& impl, std::string topic, MethodCall request, std::shared_ptr<Responder> responder,
                      const RequestOptions& options) {
    impl.send(TopicKind::method_result, std::move(topic), std::move(request), std::move(responder), options);
}
void send_method_control(Client::Impl& impl, std::string topic, MethodControlRequest request,
                         std::shared_ptr<Responder> responder, const RequestOptions& options) {
    impl.send(TopicKind::method_control_response, std::move(topic), std::move(request), std::move(responder), options);
}
std::chrono::milliseconds default_timeout(const Client::Impl& impl) { return impl.options.default_timeout; }
PendingRequests& pending_requests(Client::Impl& impl) { return impl.pending; }
bool on_dispatch_thread(const Client::Impl& impl) { return impl.dispatcher.on_dispatch_thread(); }
void send_sample_register(Client::Impl& impl, std::string topic, SampleRegisterRequest request,
                          std::shared_ptr<Responder> responder, const RequestOptions& options) {
    impl.send(TopicKind::sample_register_response, std::move(topic), std::move(request), std::move(responder), options);
}
void send_sample_unregister(Client::Impl& impl, std::string topic, SampleUnregisterRequest request,
                            std::shared_ptr<Responder> responder, const RequestOptions& options) {
    impl.send(TopicKind::sample_unregister_response, std::move(topic), std::move(request), std::move(responder),
              options);
}
Result<SubscriptionId> subscribe_sample_filter(Client::Impl& impl, std::string filter, SampleHandler handler) {
    return impl.subscribe(std::move(filter), std::move(handler));
}
// client_events.cpp (client_events.hpp)
void send_event_register(Client::Impl& impl, std::string topic, EventRegisterRequest request,
                         std::shared_ptr<Responder> responder, const RequestOptions& options) {
    impl.send(TopicKind::event_register_response, std::move(topic), std::move(request), std::move(responder), options);
}
void send_event_unregister(Client::Impl& impl, std::string topic, EventUnregisterRequest request,
                           std::shared_ptr<Responder> responder, const RequestOptions& options) {
    impl.send(TopicKind::event_unregister_response, std::move(topic), std::move(request), std::move(responder), options);
}
EventRoutes& event_routes(Client::Impl& impl) { return impl.event_routes; }
}  // namespace client_detail

}  // namespace nclink
