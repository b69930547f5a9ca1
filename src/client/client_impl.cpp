// The client's engine: the lifecycle, transport callbacks handed to the
// dispatch thread (where MessageRouter takes them), deadlines expired
// (client_impl.hpp).
#include "client/client_impl.hpp"

#include <fmt/format.h>

namespace nclink {

using client_detail::safely;

Result<void> Client::Impl::start() {
    std::lock_guard<std::mutex> lock(lifecycle_mutex);
    if (started) return make_error(ErrorCode::unavailable, "client already started");
    started = true;
    Transport& transport = link.transport();
    transport.set_message_handler([this](const Message& m) { on_message(m); });
    transport.set_state_handler([this](LinkState s, std::string_view detail) { on_link(s, detail); });
    dispatcher.start();
    // Before the first request can go out: responses must find us subscribed.
    if (auto r = transport.subscribe(client_detail::MessageRouter::response_filters(options.ex_cid), 1); !r) {
        dispatcher.stop();
        return r;
    }
    if (auto r = transport.start(); !r) {
        dispatcher.stop();
        return r;
    }
    return ok_result();
}

void Client::Impl::stop() {
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
    link.transport().stop(options.stop_flush_timeout);  // no transport callbacks after this
    dispatcher.stop();                                  // runs what is queued, then fails what is pending
}

// ---- transport callback thread: copy and hand over, never block ----
void Client::Impl::on_message(const Message& m) {
    if (!dispatcher.post([this, m] { router.route(m); })) log.debug("client: message on {} after stop dropped", m.topic);
}

void Client::Impl::on_link(LinkState state, std::string_view detail) {
    // The state machine first: wait_connected() returns into state normal.
    if (state == LinkState::connected) {
        for (auto& [id, error] : machine.link_restored()) fail_request(id, std::move(error));
    } else if (state == LinkState::disconnected) {
        machine.link_lost();
    }
    link.note(state);
    if (state == LinkState::connected) {
        keep_alive.all_due(Clock::now());  // the outage may have eaten most of the adapter's lease
        dispatcher.poke();
    }
    log.debug("client {}: link {} ({})", options.ex_cid, to_string(state), detail);
    if (options.on_link_state) dispatcher.post([this, state] { safely(log, [&] { options.on_link_state(state); }); });
}

void Client::Impl::expire(Clock::time_point now) {
    for (auto& request : pending.take_expired(now)) {
        ++counters.timeouts;
        log.debug("client: request {} timed out", request.id);
        safely(log, [&] {
            std::string message = "no response to " + request.id + " in time";
            // What the broker retained of the terminal says why, when known.
            if (const auto state = router.known_state(request.dev); state && *state != "online")
                message +=
                    fmt::format(" (device {} is {}: its retained Notify/State/{} says so)", request.dev, *state, request.dev);
            request.responder->fail(make_error(ErrorCode::timeout, message));
        });
    }
}

void Client::Impl::fail_all() {
    for (auto& request : pending.close())
        safely(log, [&] { request.responder->fail(make_error(ErrorCode::unavailable, "client stopped")); });
}

// Fails a pending request whose publish failed; on the dispatch thread when it runs.
void Client::Impl::fail_request(const std::string& id, Error error) {
    if (auto taken = pending.take(id)) {
        auto task = [this, r = std::move(taken->responder), error]() mutable { safely(log, [&] { r->fail(std::move(error)); }); };
        if (!dispatcher.post(task)) task();
    }
}

}  // namespace nclink
