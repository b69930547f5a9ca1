// Client: liveness towards the adapters (GB/T 41970-2022 3.22): the
// keep-alive Queries (client_impl.hpp, keep_alive.hpp; docs/delivery.md).
#include "client/client_impl.hpp"
#include "client/responders.hpp"

namespace nclink {

std::optional<Client::Impl::Clock::time_point> Client::Impl::next_wake() const {
    auto next = pending.next_deadline();
    const auto beat = keep_alive.next_due();
    if (beat && (!next || *beat < *next)) next = beat;
    return next;
}

// Thread: dispatch. A Query of one registered item per adapter: any DTU from
// the application keeps it online for the adapter (3.22/3.23). Sent only
// while connected (queued ones would pile up); after a reconnect all are due
// at once (on_link).
void Client::Impl::send_keepalives(Clock::time_point now) {
    if (!link.connected()) return;
    for (auto& [dev, item] : keep_alive.due(now)) {
        QueryRequest request;
        request.guid = dev;
        QueryItem query;
        query.id = item;
        request.ids.push_back(std::move(query));
        auto responder = client_detail::query_responder([this, dev = dev](Result<std::vector<QueryResult>> r) {
            if (!r) log.debug("client {}: keep-alive Query at {}: {}", options.ex_cid, dev, r.error().describe());
        });
        ++counters.keepalives;
        RequestOptions request_options;
        request_options.timeout = options.default_timeout;
        send(TopicKind::query_response, topics::query_request(dev, options.ex_cid), std::move(request), std::move(responder),
             request_options);
    }
}

}  // namespace nclink
