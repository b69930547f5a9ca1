// Request intake: every request DTU that reaches the adapter is filtered
// (retain flag, repeated @id, not for this device), handed to a worker (or,
// for a Query, to the driver's own worker), decoded, answered and the answer
// published on the topic mirroring the request (docs/wire.md).
#include "adapter/adapter_impl.hpp"
#include "adapter/request_handlers.hpp"
#include "protocol/query_request_fast.hpp"

namespace nclink {

using detail::DriverRunner;

template <class Request, class Handler>
std::optional<Json> Adapter::Impl::answer(const ParsedTopic& topic, const std::string& payload, Handler&& handler) {
    auto request = decode<Request>(payload);
    if (!request) return malformed(topic, payload, request.error());
    return handler(request.value());
}

std::optional<Json> Adapter::Impl::malformed(const ParsedTopic& topic, const std::string& payload, const Error& error) {
    ++rejected;
    logger.info("malformed {} answered NG: {}", to_string(topic.kind), error.describe());
    return make_error_reply(topic.kind, peek_message_id(payload), dev, error);
}

// Thread: transport callback. Filters, then hands the work to a request
// worker; never blocks on the driver.
void Adapter::Impl::on_message(const Message& message) {
    const auto parsed = parse_topic(message.topic);
    if (!parsed) return;
    if (parsed->kind == TopicKind::register_response) {
        on_register_response(message.payload);
        return;
    }
    if (parsed->kind == TopicKind::notify_state) {
        // A retained state comes from subscribing, not from a change: the
        // one stored before this application's current run may say offline.
        if (!message.retained) on_notify_state(*parsed, message.payload);
        return;
    }
    if (!response_kind(parsed->kind) || parsed->kind == TopicKind::probe_version ||
        parsed->kind == TopicKind::register_request || parsed->kind == TopicKind::discovery_request)
        return;  // not a request to an adapter (version-check answers and the like)
    if (parsed->dev != dev) return;
    if (parsed->ex && applications->seen(*parsed->ex, clock->now())) watch_application(*parsed->ex);
    if (message.retained) {
        // A retained request is replayed by the broker to every new
        // subscription: acting on it would repeat a stale Set.
        ++ignored_retained;
        logger.warn("ignoring retained request on {}", message.topic);
        return;
    }
    // Admitted before anything parses the payload: a flood is shed here, on
    // the transport thread, at the cost of a counter (request_gate.hpp).
    auto admission = gate->admit(message.payload.size());
    if (admission.verdict == detail::RequestGate::Verdict::shed) return;
    if (admission.verdict == detail::RequestGate::Verdict::oversized) {
        ++rejected;
        if (auto reply = make_error_reply(parsed->kind, std::nullopt, dev,
                                          make_error(ErrorCode::memory_configured,
                                                     fmt::format("request larger than {} bytes", config.max_request_bytes))))
            respond(*parsed, *reply);
        return;
    }
    // A Query is decoded here when the streaming decoder can (the common
    // case), a Set when it decodes at all: that parse reads the @id too,
    // and the worker then decodes nothing. Any other request, or one the
    // worker's decoder must refuse with its table-19 answer, has its @id
    // peeked and is decoded on the worker.
    Decoded decoded;
    if (parsed->kind == TopicKind::query_request) {
        if (auto fast = protocol_detail::fast_decode_query_request(message.payload))
            decoded.query = std::make_shared<const QueryRequest>(std::move(*fast));
    } else if (parsed->kind == TopicKind::set_request) {
        if (auto set = decode<SetRequest>(message.payload))
            decoded.set = std::make_shared<const SetRequest>(std::move(set).value());
    }
    const MessageId msg_id = decoded.query ? decoded.query->msg_id
                             : decoded.set ? decoded.set->msg_id
                                           : peek_message_id(message.payload);
    if (msg_id) {
        if (!dedup->first_sighting(detail::DedupWindow::key(to_string(parsed->kind), parsed->ex.value_or(""), *msg_id))) {
            ++ignored_duplicates;
            logger.debug("ignoring repeated request {} on {}", msg_id->dump(), message.topic);
            return;
        }
    }
    const auto received = std::chrono::steady_clock::now();
    if ((parsed->kind == TopicKind::query_request || parsed->kind == TopicKind::set_request) &&
        dispatch_driver_affine(*parsed, message.payload, admission.ticket, received, std::move(decoded)))
        return;
    executor->post([this, topic = *parsed, payload = message.payload, ticket = std::move(admission.ticket), received] {
        handle(topic, payload);
        observe_request(topic.kind, received);
    });
}

// A Query or a Set runs on the driver's own worker, which reads and writes
// in place: one thread hand-off where request worker -> driver worker ->
// back took three per driver call (bench_query_roundtrip: a 100-item Query
// went from ~1.8x to ~1.55x the bare paho floor; a Set made two driver calls,
// a read then a write, so five hand-offs). The worker cannot give up on a
// stuck driver, so the watchdog answers for it at the deadline: on a request
// worker, with 203 for the driver's items. Whichever comes first answers;
// the other is dropped. Reads are idempotent, so a Query's late duplicate
// work is harmless. A Set is marked started before the worker touches
// anything: a deadline that comes first owns it and the worker never writes
// (a write never follows a 203); one that comes after answers 203 for the
// whole Set, saying the write may still take effect.
bool Adapter::Impl::dispatch_driver_affine(const ParsedTopic& topic, const std::string& payload,
                                           std::shared_ptr<detail::RequestGate::Ticket> ticket,
                                           std::chrono::steady_clock::time_point received,
                                           Decoded decoded) {
    auto claim = std::make_shared<detail::AnswerClaim>();
    // The ticket goes with the driver's task only: the watchdog's callback
    // lives until the deadline even when the driver answered long before.
    // Unlocked: the task holds the driver only while it reads, not while it
    // parses the request or encodes the answer, so sampling gets in (a flood
    // of huge requests left a 1 ms channel a third null rows otherwise).
    const bool posted = runner->post_unlocked([this, life = lifetime, claim, topic, payload, ticket, received, decoded] {
        handle(topic, payload, Affine{claim.get(), life.get()}, nullptr, decoded);
        std::lock_guard<std::mutex> alive_lock(life->mutex);
        if (life->alive) observe_request(topic.kind, received);
    });
    if (!posted) return false;
    watchdog->arm(std::chrono::steady_clock::now() + config.driver_timeout, [this, claim, topic, payload] {
        const auto deadline = claim->claim_deadline();
        if (deadline == detail::AnswerClaim::Deadline::lost) return;
        ++affine_timeouts;
        const char* what = topic.kind == TopicKind::set_request ? "Set" : "Query";
        logger.warn("driver '{}' did not answer a {} within {} ms", driver->info().name, what, config.driver_timeout.count());
        if (deadline == detail::AnswerClaim::Deadline::during_work && topic.kind == TopicKind::set_request) {
            // The worker is inside the driver with this Set: which items it
            // has written is not known here, so the whole Set answers 203.
            const Error unknown = make_error(ErrorCode::timeout,
                                             fmt::format("driver did not finish the Set within {} ms: it may still take effect",
                                                         config.driver_timeout.count()));
            if (auto reply = make_error_reply(topic.kind, peek_message_id(payload), dev, unknown)) {
                (*reply)["privateInfo"] = Json{{"message", unknown.message}};
                executor->post([this, topic, reply = std::move(*reply)] { respond(topic, reply); });
            }
            return;
        }
        executor->post([this, topic, payload] {
            const auto ms = config.driver_timeout.count();
            const Error expired = make_error(ErrorCode::timeout,
                                             topic.kind == TopicKind::set_request
                                                 ? fmt::format("driver busy for {} ms: not written", ms)
                                                 : fmt::format("driver did not answer within {} ms", ms));
            handle(topic, payload, Affine{nullptr, nullptr}, &expired);
        });
    });
    return true;
}

// Thread: request worker, or the driver's worker for a driver-affine Query.
void Adapter::Impl::handle(const ParsedTopic& topic, const std::string& payload) {
    handle(topic, payload, Affine{nullptr, nullptr});
}

void Adapter::Impl::handle(const ParsedTopic& topic, const std::string& payload, Affine affine,
                           const Error* driver_expired, const Decoded& decoded) {
    if (affine.claim && topic.kind == TopicKind::set_request) {
        std::lock_guard<std::mutex> alive_lock(affine.life->mutex);
        if (!affine.life->alive) return;  // the adapter is gone
        if (!affine.claim->start_for_worker()) {
            logger.debug("Set dropped before it was started: the deadline answered it (not written)");
            return;
        }
    }
    ++requests;
    const auto current = host.current();
    // Copies, not references into the adapter: a driver-affine task may
    // outlive it (see Lifetime).
    const Logger task_logger = logger;
    const std::string task_dev = dev;
    // config.sampling.stats_item: the SDK-provided statistics item (docs/sampling.md)
    const auto guard = value_guard;
    detail::HandlerContext context{*current, *runner, host, task_dev, task_logger, config.sampling.stats_item,
                                   [this] { return to_json(self->stats()); }, driver_expired, guard.get()};
    std::optional<Json> reply;
    std::optional<std::string> text;  // an answer already written out (a Query's, a Set's)
    switch (topic.kind) {
        case TopicKind::query_request: {
            if (decoded.query) {
                text = detail::handle_query(*decoded.query, context);
                break;
            }
            auto request = decode<QueryRequest>(payload);
            if (!request) {
                reply = malformed(topic, payload, request.error());
                break;
            }
            text = detail::handle_query(request.value(), context);
            break;
        }
        case TopicKind::set_request:
            if (decoded.set) {
                text = encode(detail::handle_set(*decoded.set, context));
                break;
            }
            reply = answer<SetRequest>(topic, payload, [&](const SetRequest& r) { return to_json(detail::handle_set(r, context)); });
            break;
        case TopicKind::probe_query_request: {
            auto request = decode<ProbeQueryRequest>(payload);
            if (request) {
                respond_text(topic, detail::handle_probe_query(request.value(), context));
                return;
            }
            reply = malformed(topic, payload, request.error());
            break;
        }
        case TopicKind::probe_set_request:
            reply = answer<ProbeSetRequest>(topic, payload, [&](const ProbeSetRequest& r) { return to_json(probe_set(r)); });
            break;
        default:
            for (auto& service : features) {
                if (service->handles(topic.kind)) {
                    service->handle(topic, payload);
                    return;
                }
            }
            // Requests of features this adapter does not run: never
            // silence, always an answer (docs/wire.md "Error answers").
            ++rejected;
            reply = make_error_reply(topic.kind, peek_message_id(payload), dev,
                                     make_error(ErrorCode::unavailable, "not supported by this adapter"));
            break;
    }
    if (!reply && !text) return;
    const auto deliver = [&] {
        if (text)
            respond_text(topic, std::move(*text));
        else
            respond(topic, *reply);
    };
    if (!affine.claim) {
        deliver();
        return;
    }
    std::lock_guard<std::mutex> alive_lock(affine.life->mutex);
    if (!affine.life->alive) return;  // the adapter is gone
    if (!affine.claim->claim_for_worker()) {
        logger.debug("late {} answer dropped: the deadline answered it", to_string(topic.kind));
        return;
    }
    deliver();
}

void Adapter::Impl::respond(const ParsedTopic& request_topic, const Json& reply) {
    // A registration's answer names this run of the adapter in privateInfo
    // (the implementation's, 8.2.18/8.2.28), as Probe/Version does: the
    // application then knows, after an outage, whether the registration is
    // still here (same run) or must be made again (docs/wire.md).
    if ((request_topic.kind == TopicKind::event_register_request ||
         request_topic.kind == TopicKind::sample_register_request) &&
        reply.is_object() && (!reply.contains("privateInfo") || reply["privateInfo"].is_object() || reply["privateInfo"].is_null())) {
        Json marked = reply;
        if (!marked["privateInfo"].is_object()) marked["privateInfo"] = Json::object();
        marked["privateInfo"]["instance"] = instance;
        respond_text(request_topic, marked.dump(-1, ' ', false, Json::error_handler_t::replace));
        return;
    }
    respond_text(request_topic, reply.dump(-1, ' ', false, Json::error_handler_t::replace));
}

void Adapter::Impl::respond_text(const ParsedTopic& request_topic, std::string payload) {
    std::vector<Message> response;
    auto topics = response_topics(request_topic, config.standard_typo_topics);
    response.reserve(topics.size());
    for (std::size_t i = 0; i < topics.size(); ++i)
        response.push_back(Message{std::move(topics[i]), i + 1 == topics.size() ? std::move(payload) : payload, 1, false});
    // Sent, or kept for later: the state machine's row decides (the state-machine text 69, 74, 79).
    fire(AdapterEvent::request_handled, std::move(response));
}


}  // namespace nclink
