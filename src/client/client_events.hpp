// Events on the client side (8.2.27-8.2.31): which callback gets the Event
// DTUs of which registration, what client.cpp routes to it, and the few core
// services client_events.cpp borrows from client.cpp (which alone sees
// Client::Impl).
#pragma once

#include "client/pending_requests.hpp"

#include <nclink/client.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

namespace nclink::client_detail {

/// The callbacks of this client's event registrations, by (dev, event id).
/// Internally synchronized: added on the dispatch thread (when the
/// registration's OK arrives), removed from any thread.
class EventRoutes {
public:
    enum class Delivery { delivered, unknown_event, malformed };

    void add(const std::string& dev, const std::string& event_id, Client::EventHandler handler, bool once);
    /// false when there was no such route.
    bool remove(const std::string& dev, const std::string& event_id);
    /// An Event DTU that arrived on Event/{dev}/{ex}: calls its registration's
    /// callback (dispatch thread). A once registration's route goes with its
    /// first event (the adapter released it).
    Delivery deliver(const std::string& dev, const std::string& payload, const Logger& log);
    std::size_t size() const;

private:
    struct Route {
        std::shared_ptr<const Client::EventHandler> handler;
        bool once = false;
    };
    mutable std::mutex mutex_;
    std::map<std::pair<std::string, std::string>, Route> routes_;
};

// ---- implemented in client.cpp, called by client_events.cpp (any thread)

/// Publishes Register/Event (answered on Register/Event/Response) or
/// Unregister/Event through the client core, which sets @id and privateInfo
/// and tracks the answer.
void send_event_register(Client::Impl& impl, std::string topic, EventRegisterRequest request,
                         std::shared_ptr<Responder> responder, const RequestOptions& options);
void send_event_unregister(Client::Impl& impl, std::string topic, EventUnregisterRequest request,
                           std::shared_ptr<Responder> responder, const RequestOptions& options);
EventRoutes& event_routes(Client::Impl& impl);

}  // namespace nclink::client_detail
