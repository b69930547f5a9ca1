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
    Result<Outcome> submit(const std::string& id, Message message, const std::function<bool()>& add);
    /// The link came up: queued requests still pending are published in
    /// order. Returns those whose publish failed, with the error.
    std::vector<std::pair<std::string, Error>> link_restored();
    void link_lost();
    /// A request completed (answer, error or timeout).
    void completed();
    /// A response nobody waits for arrived (dropped).
    void stray_response();

    ClientState state() const;
    std::size_t queued() const;

private:
    void apply(ClientEvent event, bool queued = false, bool outstanding = false);
    void prune();  // drops queued entries that are no longer pending

    Hooks hooks_;
    const std::size_t max_queued_;
    mutable std::mutex mutex_;
    ClientState state_ = ClientState::initial;
    std::deque<std::pair<std::string, Message>> queue_;
};

/// Wraps a responder so that `on_done` (the machine's completed() event) runs
/// on the same thread just before it completes or fails.
std::shared_ptr<Responder> track_completion(std::shared_ptr<Responder> inner, std::function<void()> on_done);

}  // namespace nclink::client_detail
