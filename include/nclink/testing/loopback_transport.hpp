// In-process transport: a tiny broker object and transports attached to it.
// For unit tests of everything above the transport (no sockets, no threads
// beyond the broker's delivery thread and each transport's sender), with
// fault injection: take the broker down, drop one client.
#pragma once

#include <nclink/export.hpp>
#include <nclink/log.hpp>
#include <nclink/transport.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace nclink {

/// MQTT-like semantics: topic filters with + and #, retained messages
/// (an empty retained payload clears), last wills on abnormal disconnects,
/// subscriptions cleared on disconnect (clean sessions; transports
/// resubscribe). Every handler of every attached transport runs on the
/// broker's one delivery thread, in order.
/// Thread-safety: every member function may be called from any thread except
/// from inside a transport handler where noted.
class NCLINK_API LoopbackBroker {
public:
    LoopbackBroker();
    ~LoopbackBroker();
    LoopbackBroker(const LoopbackBroker&) = delete;
    LoopbackBroker& operator=(const LoopbackBroker&) = delete;

    /// false: every attached client loses its link (wills are published and
    /// retained ones kept) and publishes are refused; true: clients reconnect.
    void set_online(bool online);
    bool online() const;

    /// Abnormal disconnect of one client (its will is published); it
    /// reconnects at once, as a real client with automatic reconnect would.
    /// Returns false when no such client is attached.
    bool drop_client(const std::string& client_id);

    /// The retained message of a topic, if any.
    std::optional<Message> retained(const std::string& topic) const;

    /// Messages routed so far (each publish counts once).
    std::uint64_t routed() const;

    struct Impl;

private:
    friend class LoopbackAccess;
    std::shared_ptr<Impl> impl_;
};

struct NCLINK_API LoopbackOptions {
    std::string client_id;
    std::optional<Message> last_will;
    OutboxLimits outbox;
};

/// A transport attached to `broker` (which must outlive it).
NCLINK_API std::unique_ptr<Transport> make_loopback_transport(LoopbackBroker& broker, LoopbackOptions options, Logger logger = {});

}  // namespace nclink
