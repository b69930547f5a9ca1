// Every DTU the client receives, on the dispatch thread: a response goes to
// its pending request by @id, an own Event or Method/Status to the call or
// registration that asked for it, and every DTU to the subscriptions whose
// filter it matches (Sample, Notify/State, Probe/Version, Event, Method
// runs). QoS 1 repeats are handed on once (DuplicateFilter), and the last
// Notify/State per terminal is remembered so a timeout can name a retained
// "offline" (8.2.16).
// The router owns that memory; the link's subscriptions, the pending
// requests and the event registrations are the client's, lent to it.
// Thread: the dispatch thread only (not synchronized).
#pragma once

#include "client/client_counters.hpp"
#include "client/client_events.hpp"
#include "client/client_link.hpp"
#include "client/duplicate_filter.hpp"
#include "client/pending_requests.hpp"
#include "client/safely.hpp"

#include <nclink/log.hpp>
#include <nclink/topics.hpp>
#include <nclink/transport.hpp>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>

namespace nclink::client_detail {

class MessageRouter {
public:
    struct Parts {
        std::string ex_cid;  ///< this application's id: the last level of its own topics
        Logger log;
        ClientCounters& counters;
        const ClientLink& link;     ///< subscriptions matched against each topic
        PendingRequests& pending;   ///< responses by @id
        EventRoutes& event_routes;  ///< this client's own event registrations
        /// A register answer names the adapter run it came from
        /// (privateInfo.instance): the model cache records it.
        std::function<void(const std::string& dev, const std::string& payload)> note_instance;
    };

    MessageRouter(Parts parts, std::size_t duplicate_memory) : p_(std::move(parts)), duplicates_(duplicate_memory) {}

    /// The topic filters a client subscribes to get its own answers.
    static std::vector<std::string> response_filters(const std::string& ex_cid);

    void route(const Message& m);

    /// The last state the terminal announced on Notify/State, when one was
    /// seen (a cleared retained state forgets it).
    std::optional<std::string> known_state(const std::string& dev) const;

private:
    void handle_response(const ParsedTopic& topic, const std::string& payload);
    void handle_notification(const ParsedTopic& topic, const Message& m);
    /// Event/{dev}/{ex}: this client's own go to their registrations
    /// (client_events.cpp), every one to subscribe_events() handlers.
    void handle_event(const ParsedTopic& topic, const Message& m);
    /// Method/Status and Method/Result/{dev}/{ex}: this client's own go to
    /// their calls (client_methods.cpp), every one to subscribe_method_runs() handlers.
    void handle_method_run(const ParsedTopic& topic, const Message& m);
    /// False for a Sample/Event DTU already handed on (counted): Samples by
    /// topic and beginTime, Events by device and @id.
    bool first_delivery(const std::string& stream, const std::string& key);

    template <class Handler, class Dtu>
    void deliver_to(const std::vector<std::shared_ptr<Subscription>>& subs, const Dtu& dtu, std::atomic<std::uint64_t>& counter) {
        for (const auto& sub : subs) {
            const auto* handler = std::get_if<Handler>(&sub->handler);
            if (!handler || !*handler || !sub->alive) continue;
            ++counter;
            safely(p_.log, [&] { (*handler)(dtu); });
        }
    }

    Parts p_;
    DuplicateFilter duplicates_;
    std::map<std::string, std::string> known_states_;
};

}  // namespace nclink::client_detail
