// The client's state (docs/state-machines.md, include/nclink/client_state.hpp) and the
// queue of requests made while the link is down. It sits in the send path:
// every request goes through submit(), every link change through
// link_restored()/link_lost(), every completion through completed().
//
// Queued requests keep the deadline they got when made (docs/client.md): a
// request that times out while queued is failed with 203 by the client and
// never sent -- a Set must not reach a machine minutes after the caller gave
// up on it.
//
// 8.3.6 (both links down, e.g. the broker restarts): the queue goes out when
// the application's own link returns, which may be before the adapter has
// subscribed again; the broker then drops it. Those requests are kept until
// answered and published again (same @id: the adapter ignores a repeat) when
// their device announces itself with Probe/Version, which it sends only after
// subscribing (8.2.5; resend()). A second outage puts them back in the queue.
//
// Thread-safety: every member may be called from any thread. The table
// callbacks (is_pending, outstanding) are called with the machine's lock
// held; they must not call back into the machine.
#pragma once

#include "client/pending_requests.hpp"

#include <nclink/client_state.hpp>
#include <nclink/result.hpp>
#include <nclink/transport.hpp>

#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace nclink::client_detail {

class ClientStateMachine {
public:
    using Publish = std::function<Result<void>(Message)>;

    struct Hooks {
        std::function<bool(const std::string& id)> is_pending;  ///< the request still waits (not timed out)
        std::function<bool()> outstanding;                      ///< any request waits
        Publish publish;                                        ///< hands a message to the transport
    };

    ClientStateMachine(Hooks hooks, std::size_t max_queued) : hooks_(std::move(hooks)), max_queued_(max_queued) {}

    enum class Outcome { sent, queued };
    /// A request was made: `add` enters it in the pending table (false: the
    /// client is closing -> unavailable). Sent at once when connected, queued
    /// otherwise (404 when max_queued requests already wait).
    Result<Outcome> submit(const std::string& id, const std::string& dev, Message message, const std::function<bool()>& add);
    /// The link came up: queued requests still pending are published in
    /// order. Returns those whose publish failed, with the error.
    std::vector<std::pair<std::string, Error>> link_restored();
    void link_lost();
    /// `dev` announced itself (Probe/Version): the requests to it that went
    /// out from the queue and still wait are published again. `sent` counts
    /// them; returns those whose publish failed.
    std::vector<std::pair<std::string, Error>> resend(const std::string& dev, std::size_t& sent);
    /// A request completed (answer, error or timeout).
    void completed();
    /// A response nobody waits for arrived (dropped).
    void stray_response();

    ClientState state() const;
    std::size_t queued() const;

private:
    void apply(ClientEvent event, bool queued = false, bool outstanding = false);
    struct Entry {
        std::string id;
        std::string dev;
        Message message;
    };
    void prune(std::deque<Entry>& entries);  // drops entries that are no longer pending

    Hooks hooks_;
    const std::size_t max_queued_;
    mutable std::mutex mutex_;
    ClientState state_ = ClientState::initial;
    std::deque<Entry> queue_;
    std::deque<Entry> unconfirmed_;  ///< went out from the queue, not answered yet
};

/// Wraps a responder so that `on_done` (the machine's completed() event) runs
/// on the same thread just before it completes or fails.
std::shared_ptr<Responder> track_completion(std::shared_ptr<Responder> inner, std::function<void()> on_done);

}  // namespace nclink::client_detail
