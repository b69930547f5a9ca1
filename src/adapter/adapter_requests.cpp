// Request intake (adapter_requests.hpp): every request DTU that reaches the
// adapter is filtered (retain flag, repeated @id, not for this device),
// handed to a worker (or, for a Query or a Set, to the driver's own worker),
// decoded, answered and the answer published on the topic mirroring the
// request (docs/wire.md).
#include "adapter/adapter_requests.hpp"
#include "adapter/request_handlers.hpp"
#include "protocol/query_request_fast.hpp"

namespace nclink::adapter_detail {

namespace {
constexpr std::chrono::milliseconds kBurstWorkerLinger{2000};
}  // namespace

RequestIntake::RequestIntake(Parts parts)
    : parts_(std::move(parts)),
      gate_(std::make_shared<RequestGate>(parts_.config.max_pending_requests, parts_.config.max_request_bytes, parts_.logger)),
      dedup_(parts_.config.dedup_window, parts_.config.dedup_capacity, parts_.clock) {
    if (parts_.shared) {
        executor_ = std::make_unique<core_detail::TaskGroup>(parts_.shared->requests);
        watchdog_ = std::make_unique<core_detail::WatchdogScope>(parts_.shared->watchdog);
    } else {
        // One worker always; the others (request_threads in all) start when
        // requests queue up and end after kBurstWorkerLinger without one, so
        // an idle terminal runs one request thread (docs/footprint.md).
        own_executor_ = std::make_shared<core_detail::Executor>(parts_.config.request_threads, 1, kBurstWorkerLinger);
        executor_ = std::make_unique<core_detail::TaskGroup>(own_executor_);
        own_watchdog_ = std::make_unique<core_detail::DeadlineWatchdog>(parts_.background);
        watchdog_ = std::make_unique<core_detail::WatchdogScope>(*own_watchdog_);
    }
}

void RequestIntake::close() {
    watchdog_->close();
    if (own_watchdog_) own_watchdog_->stop();
    executor_->close();  // answers what is queued
    if (own_executor_) own_executor_->stop();
}

void RequestIntake::release_driver_tasks() {
    std::lock_guard<std::mutex> lock(lifetime_->mutex);
    lifetime_->alive = false;
}

RequestIntake::Counts RequestIntake::counts() const {
    Counts c;
    c.requests = requests_;
    c.ignored_retained = ignored_retained_;
    c.ignored_duplicates = ignored_duplicates_;
    c.rejected = rejected_;
    c.affine_timeouts = affine_timeouts_;
    c.shed = gate_->shed();
    c.oversized = gate_->oversized();
    c.pending = gate_->pending();
    return c;
}

void RequestIntake::observe(TopicKind kind, std::chrono::steady_clock::time_point received) noexcept {
    const auto index = static_cast<std::size_t>(kind);
    if (index < latency_.size()) latency_[index].observe(std::chrono::steady_clock::now() - received);
}

void RequestIntake::add_latency(TrafficStats& out) const {
    for (std::size_t i = 0; i < latency_.size(); ++i) {
        if (latency_[i].count() == 0) continue;
        out.request_seconds[std::string(to_string(static_cast<TopicKind>(i)))] = latency_[i].snapshot();
    }
}

template <class Request, class Handler>
std::optional<Json> RequestIntake::answer(const ParsedTopic& topic, const std::string& payload, Handler&& handler) {
    auto request = decode<Request>(payload);
    if (!request) return malformed(topic, payload, request.error());
    return handler(request.value());
}

std::optional<Json> RequestIntake::malformed(const ParsedTopic& topic, const std::string& payload, const Error& error) {
    ++rejected_;
    parts_.logger.info("malformed {} answered NG: {}", to_string(topic.kind), error.describe());
    return make_error_reply(topic.kind, peek_message_id(payload), parts_.dev, error);
}

// Thread: transport callback. Filters, then hands the work to a request
// worker; never blocks on the driver.
void RequestIntake::on_request(const ParsedTopic& topic, const Message& message) {
    const auto& config = parts_.config;
    const auto& logger = parts_.logger;
    const auto& dev = parts_.dev;
    if (!response_kind(topic.kind) || topic.kind == TopicKind::probe_version || topic.kind == TopicKind::register_request ||
        topic.kind == TopicKind::discovery_request)
        return;  // not a request to an adapter (version-check answers and the like)
    if (topic.dev != dev) return;
    if (topic.ex) parts_.applications.seen(*topic.ex, parts_.clock->now());
    if (message.retained) {
        // A retained request is replayed by the broker to every new
        // subscription: acting on it would repeat a stale Set.
        ++ignored_retained_;
        logger.warn("ignoring retained request on {}", message.topic);
        return;
    }
    // Admitted before anything parses the payload: a flood is shed here, on
    // the transport thread, at the cost of a counter (request_gate.hpp).
    auto admission = gate_->admit(message.payload.size());
    if (admission.verdict == RequestGate::Verdict::shed) return;
    if (admission.verdict == RequestGate::Verdict::oversized) {
        ++rejected_;
        if (auto reply = make_error_reply(
                topic.kind, std::nullopt, dev,
                make_error(ErrorCode::memory_configured, fmt::format("request larger than {} bytes", config.max_request_bytes))))
            parts_.link.respond(topic, *reply);
        return;
    }
    // A Query is decoded here when the streaming decoder can (the common
    // case), a Set when it decodes at all: that parse reads the @id too,
    // and the worker then decodes nothing. Any other request, or one the
    // worker's decoder must refuse with its table-19 answer, has its @id
    // peeked and is decoded on the worker.
    Decoded decoded;
    if (topic.kind == TopicKind::query_request) {
        if (auto fast = protocol_detail::fast_decode_query_request(message.payload))
            decoded.query = std::make_shared<const QueryRequest>(std::move(*fast));
    } else if (topic.kind == TopicKind::set_request) {
        if (auto set = decode<SetRequest>(message.payload))
            decoded.set = std::make_shared<const SetRequest>(std::move(set).value());
    }
    const MessageId msg_id = decoded.query ? decoded.query->msg_id
                             : decoded.set ? decoded.set->msg_id
                                           : peek_message_id(message.payload);
    if (msg_id) {
        if (!dedup_.first_sighting(DedupWindow::key(to_string(topic.kind), topic.ex.value_or(""), *msg_id))) {
            ++ignored_duplicates_;
            logger.debug("ignoring repeated request {} on {}", msg_id->dump(), message.topic);
            return;
        }
    }
    const auto received = std::chrono::steady_clock::now();
    if ((topic.kind == TopicKind::query_request || topic.kind == TopicKind::set_request) &&
        dispatch_driver_affine(topic, message.payload, admission.ticket, received, std::move(decoded)))
        return;
    executor_->post([this, topic, payload = message.payload, ticket = std::move(admission.ticket), received] {
        handle(topic, payload);
        observe(topic.kind, received);
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
bool RequestIntake::dispatch_driver_affine(const ParsedTopic& topic, const std::string& payload,
                                           std::shared_ptr<RequestGate::Ticket> ticket,
                                           std::chrono::steady_clock::time_point received, Decoded decoded) {
    const auto& config = parts_.config;
    auto claim = std::make_shared<core_detail::AnswerClaim>();
    // The ticket goes with the driver's task only: the watchdog's callback
    // lives until the deadline even when the driver answered long before.
    // Unlocked: the task holds the driver only while it reads, not while it
    // parses the request or encodes the answer, so sampling gets in (a flood
    // of huge requests left a 1 ms channel a third null rows otherwise).
    const bool posted = parts_.runner.post_unlocked([this, life = lifetime_, claim, topic, payload, ticket, received, decoded] {
        handle(topic, payload, Affine{claim.get(), life.get()}, nullptr, decoded);
        std::lock_guard<std::mutex> alive_lock(life->mutex);
        if (life->alive) observe(topic.kind, received);
    });
    if (!posted) return false;
    watchdog_->arm(std::chrono::steady_clock::now() + config.driver_timeout, [this, claim, topic, payload] {
        const auto timeout = parts_.config.driver_timeout;
        const auto deadline = claim->claim_deadline();
        if (deadline == core_detail::AnswerClaim::Deadline::lost) return;
        ++affine_timeouts_;
        const char* what = topic.kind == TopicKind::set_request ? "Set" : "Query";
        parts_.logger.warn("driver '{}' did not answer a {} within {} ms", parts_.driver.info().name, what, timeout.count());
        if (deadline == core_detail::AnswerClaim::Deadline::during_work && topic.kind == TopicKind::set_request) {
            // The worker is inside the driver with this Set: which items it
            // has written is not known here, so the whole Set answers 203.
            const Error unknown =
                make_error(ErrorCode::timeout,
                           fmt::format("driver did not finish the Set within {} ms: it may still take effect", timeout.count()));
            if (auto reply = make_error_reply(topic.kind, peek_message_id(payload), parts_.dev, unknown)) {
                (*reply)["privateInfo"] = Json{{"message", unknown.message}};
                executor_->post([this, topic, reply = std::move(*reply)] { parts_.link.respond(topic, reply); });
            }
            return;
        }
        executor_->post([this, topic, payload] {
            const auto ms = parts_.config.driver_timeout.count();
            const Error expired = make_error(ErrorCode::timeout, topic.kind == TopicKind::set_request
                                                                     ? fmt::format("driver busy for {} ms: not written", ms)
                                                                     : fmt::format("driver did not answer within {} ms", ms));
            handle(topic, payload, Affine{nullptr, nullptr}, &expired);
        });
    });
    return true;
}

// Thread: request worker, or the driver's worker for a driver-affine Query.
void RequestIntake::handle(const ParsedTopic& topic, const std::string& payload) {
    handle(topic, payload, Affine{nullptr, nullptr});
}

void RequestIntake::handle(const ParsedTopic& topic, const std::string& payload, Affine affine, const Error* driver_expired,
                           const Decoded& decoded) {
    const auto& logger = parts_.logger;
    if (affine.claim && topic.kind == TopicKind::set_request) {
        std::lock_guard<std::mutex> alive_lock(affine.life->mutex);
        if (!affine.life->alive) return;  // the adapter is gone
        if (!affine.claim->start_for_worker()) {
            logger.debug("Set dropped before it was started: the deadline answered it (not written)");
            return;
        }
    }
    ++requests_;
    const auto current = parts_.host.current();
    // Copies, not references into the adapter: a driver-affine task may
    // outlive it (see Lifetime).
    const Logger task_logger = logger;
    const std::string task_dev = parts_.dev;
    // config.sampling.stats_item: the SDK-provided statistics item (docs/sampling.md)
    const auto guard = parts_.values;
    HandlerContext context{*current,          parts_.runner,  parts_.host,
                           task_dev,          task_logger,    parts_.config.sampling.stats_item,
                           parts_.statistics, driver_expired, guard.get()};
    std::optional<Json> reply;
    std::optional<std::string> text;  // an answer already written out (a Query's, a Set's)
    switch (topic.kind) {
        case TopicKind::query_request: {
            if (decoded.query) {
                text = handle_query(*decoded.query, context);
                break;
            }
            auto request = decode<QueryRequest>(payload);
            if (!request) {
                reply = malformed(topic, payload, request.error());
                break;
            }
            text = handle_query(request.value(), context);
            break;
        }
        case TopicKind::set_request:
            if (decoded.set) {
                text = encode(handle_set(*decoded.set, context));
                break;
            }
            reply = answer<SetRequest>(topic, payload, [&](const SetRequest& r) { return to_json(handle_set(r, context)); });
            break;
        case TopicKind::probe_query_request: {
            auto request = decode<ProbeQueryRequest>(payload);
            if (request) {
                parts_.link.respond_text(topic, handle_probe_query(request.value(), context));
                return;
            }
            reply = malformed(topic, payload, request.error());
            break;
        }
        case TopicKind::probe_set_request:
            reply = answer<ProbeSetRequest>(topic, payload,
                                            [&](const ProbeSetRequest& r) { return to_json(parts_.model_change.probe_set(r)); });
            break;
        default:
            if (parts_.features.handle(topic, payload)) return;
            // Requests of features this adapter does not run: never
            // silence, always an answer (docs/wire.md "Error answers").
            ++rejected_;
            reply = make_error_reply(topic.kind, peek_message_id(payload), parts_.dev,
                                     make_error(ErrorCode::unavailable, "not supported by this adapter"));
            break;
    }
    if (!reply && !text) return;
    const auto deliver = [&] {
        if (text) parts_.link.respond_text(topic, std::move(*text));
        else parts_.link.respond(topic, *reply);
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

}  // namespace nclink::adapter_detail
