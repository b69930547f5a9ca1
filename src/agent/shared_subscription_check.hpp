// Does the broker deliver through `$share/{group}/{filter}` (MQTT 5 4.8.2)?
// An agent answers requests through shared subscriptions by default, and a
// broker without them hears nothing of the agent or drops it: RabbitMQ 3.10
// takes `$share/...` for a topic name and delivers nothing to it, ejabberd
// 23.01 ends the connection at the SUBSCRIBE (docs/scaling.md). Neither
// says so at CONNECT (a 3.1.1 CONNACK has no "Shared Subscription
// Available"), so the check tries it: a connection of its own subscribes
// `$share/{group}-check/{topic}` and publishes to `{topic}` until the
// message comes back, the connection ends, or `timeout` passes.
//
// The group is the caller's with "-check" appended, so the check's message
// is never handed to another instance of the caller's real group.
#pragma once

#include <nclink/transport.hpp>

#include <chrono>
#include <string>

namespace nclink::agent_detail {

enum class SharedSubscriptions { available, unavailable, unknown };

struct SharedSubscriptionCheck {
    SharedSubscriptions result = SharedSubscriptions::unknown;
    std::string detail;  ///< what was seen, for the log
};

/// Runs the check over `probe`: a transport not yet started, with a client
/// id of its own (not the caller's, whose session it would take over). It is
/// stopped before this returns. `unknown` when it never connected within
/// `connect_timeout`.
SharedSubscriptionCheck check_shared_subscriptions(Transport& probe, const std::string& group, const std::string& topic,
                                                   std::chrono::milliseconds connect_timeout, std::chrono::milliseconds timeout);

}  // namespace nclink::agent_detail
