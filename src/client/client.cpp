// The client's public facade: create, lifecycle, the core requests of
// chapter 8 (register, discovery, probe, query, set) in their asynchronous and
// blocking forms, subscriptions and statistics. The engine behind it is
// client_impl.cpp.
#include <nclink/client.hpp>
#include <nclink/paho_transport.hpp>

#include "client/blocking_call.hpp"
#include "client/client_impl.hpp"
#include "client/discovery_responder.hpp"

#include <nclink/topics.hpp>

#include <mutex>
#include <utility>

namespace nclink {

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

}  // namespace

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
    auto transport = make_paho_transport(std::move(mqtt), options.logger);  // MQTT 5, ws:// (paho_transport.hpp)
    if (!transport) return std::move(transport).error();
    return create(std::move(transport).value(), std::move(options));
}

Client::Client(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) { impl_->owner = this; }

Client::~Client() {
    if (impl_) impl_->stop();
}

Result<void> Client::start() { return impl_->start(); }

bool Client::wait_connected(std::chrono::milliseconds timeout) { return impl_->link.wait_connected(timeout); }

Result<RegisterOutcome> Client::connect(std::chrono::milliseconds timeout) {
    bool need_start = false;
    {
        std::lock_guard<std::mutex> lock(impl_->lifecycle_mutex);
        need_start = !impl_->started;
    }
    if (need_start)
        if (auto r = start(); !r) return std::move(r).error();
    // Connected, or refused (credentials, a certificate: no use waiting on).
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!wait_connected(std::chrono::milliseconds(20)) && !impl_->link.transport().stats().refused &&
           std::chrono::steady_clock::now() < deadline) {
    }
    if (!wait_connected(std::chrono::milliseconds(0))) {
        const TransportStats link = impl_->link.transport().stats();
        if (link.refused) return make_error(ErrorCode::permission_denied, "cannot connect to the broker: " + link.last_error);
        return make_error(ErrorCode::timeout, "no connection to the broker within " + std::to_string(timeout.count()) + " ms" +
                                                  (link.last_error.empty() ? "" : ": " + link.last_error));
    }
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
    impl_->send(TopicKind::probe_query_response, topics::probe_query_request(dev, impl_->options.ex_cid), std::move(request),
                client_detail::probe_responder(std::move(done)), options);
}

void Client::probe_set_async(const std::string& dev, Json model, Completion<void> done, RequestOptions options) {
    ProbeSetRequest request;
    request.guid = dev;
    request.probe = std::move(model);
    impl_->send(TopicKind::probe_set_response, topics::probe_set_request(dev, impl_->options.ex_cid), std::move(request),
                client_detail::probe_set_responder(std::move(done)), options);
}

void Client::query_async(const std::string& dev, std::vector<QueryItem> items, Completion<std::vector<QueryResult>> done,
                         RequestOptions options) {
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
    return client_detail::wait_for<std::vector<DeviceListEntry>>(*impl_,
                                                                 [&](auto done) { discover_async(std::move(done), options); });
}

Result<RegisterOutcome> Client::register_terminal(RequestOptions options) {
    return client_detail::wait_for<RegisterOutcome>(*impl_, [&](auto done) { register_async(std::move(done), options); });
}

Result<Json> Client::probe(const std::string& dev, RequestOptions options) {
    return client_detail::wait_for<Json>(*impl_, [&](auto done) { probe_async(dev, std::move(done), options); });
}

Result<void> Client::probe_set(const std::string& dev, Json model, RequestOptions options) {
    return client_detail::wait_for<void>(*impl_,
                                         [&](auto done) { probe_set_async(dev, std::move(model), std::move(done), options); });
}

Result<std::vector<QueryResult>> Client::query(const std::string& dev, std::vector<QueryItem> items, RequestOptions options) {
    return client_detail::wait_for<std::vector<QueryResult>>(
        *impl_, [&](auto done) { query_async(dev, std::move(items), std::move(done), options); });
}

Result<std::vector<SetResult>> Client::set(const std::string& dev, std::vector<SetItem> items, RequestOptions options) {
    return client_detail::wait_for<std::vector<SetResult>>(
        *impl_, [&](auto done) { set_async(dev, std::move(items), std::move(done), options); });
}

Result<SubscriptionId> Client::subscribe_samples(const std::string& dev, SampleHandler handler, std::optional<std::string> channel) {
    if (!valid_topic_level(dev)) return make_error(ErrorCode::value_type, "subscribe_samples: bad device id");
    if (channel && !valid_topic_level(*channel)) return make_error(ErrorCode::value_type, "subscribe_samples: bad channel id");
    return impl_->link.subscribe(topics::sample(dev, channel ? std::string_view(*channel) : std::string_view("+")),
                                 std::move(handler));
}

Result<SubscriptionId> Client::subscribe_state(const std::string& tid, StateHandler handler) {
    if (!valid_topic_level(tid)) return make_error(ErrorCode::value_type, "subscribe_state: bad terminal id");
    return impl_->link.subscribe(topics::notify_state(tid), std::move(handler));
}

Result<SubscriptionId> Client::subscribe_all_states(StateHandler handler) {
    return impl_->link.subscribe(topics::notify_state("+"), std::move(handler));
}

Result<SubscriptionId> Client::subscribe_version(const std::string& dev, VersionHandler handler) {
    if (!valid_topic_level(dev)) return make_error(ErrorCode::value_type, "subscribe_version: bad device id");
    return impl_->link.subscribe(topics::probe_version(dev), std::move(handler));
}

Result<SubscriptionId> Client::subscribe_method_runs(const std::string& dev, MethodRunHandler handler) {
    if (!valid_topic_level(dev)) return make_error(ErrorCode::value_type, "subscribe_method_runs: bad device id");
    return impl_->link.subscribe(std::vector<std::string>{topics::method_status(dev, "+"), topics::method_result(dev, "+")},
                                 std::move(handler));
}

Result<SubscriptionId> Client::subscribe_events(const std::string& dev, WatchedEventHandler handler) {
    if (!valid_topic_level(dev)) return make_error(ErrorCode::value_type, "subscribe_events: bad device id");
    return impl_->link.subscribe(topics::event(dev, "+"), std::move(handler));
}

std::string_view to_string(MethodRun::Kind kind) noexcept {
    switch (kind) {
        case MethodRun::Kind::status: return "status";
        case MethodRun::Kind::result: return "result";
    }
    return "?";
}

Result<void> Client::unsubscribe(SubscriptionId id) { return impl_->link.unsubscribe(id); }

const std::string& Client::ex_cid() const noexcept { return impl_->options.ex_cid; }

LinkState Client::link_state() const { return impl_->link.state(); }

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
    s.transport = impl_->link.transport().stats();
    s.events = c.events;
    s.duplicates = c.duplicates;
    s.keepalives = c.keepalives;
    s.resent = c.resent;
    return s;
}

std::size_t Client::pending_requests() const { return impl_->pending.size(); }

const Transport& Client::transport() const noexcept { return impl_->link.transport(); }

}  // namespace nclink
