// Events on the client side (8.2.27-8.2.31): which callback gets the Event
// DTUs of which registration (the client's engine routes Event DTUs here).
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

}  // namespace nclink::client_detail
