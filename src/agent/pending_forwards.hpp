// Requests the agent saw go to an adapter and waits to see answered (8.3.5):
// answered -> forgotten; overdue -> the agent answers 203; the adapter goes
// offline -> the agent answers DEV_UNREACHABLE. Pure bookkeeping.
#pragma once

#include <nclink/clock.hpp>
#include <nclink/dtu_common.hpp>
#include <nclink/topics.hpp>

#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace nclink::agent_detail {

struct Forwarded {
    TopicKind kind = TopicKind::query_request;  ///< the request's kind
    std::string dev;
    std::optional<std::string> ex;
    MessageId msg_id;
    std::string topic;  ///< the request topic (its answer mirrors it)
    Clock::Steady deadline{};
};

class PendingForwards {
public:
    /// Requests without "@id" cannot be matched to an answer: not tracked.
    void add(Forwarded request);
    /// A response of `answer_kind` from `dev` to `ex` with `id` arrived:
    /// true when it answered a tracked request (which is forgotten).
    bool answered(TopicKind answer_kind, const std::string& dev, const std::optional<std::string>& ex, const std::string& id);
    std::vector<Forwarded> take_expired(Clock::Steady now);
    std::vector<Forwarded> take_for(const std::string& dev);
    std::size_t size() const { return by_key_.size(); }

private:
    using Key = std::tuple<std::string, std::string, std::string, int>;  // dev, ex ("" = none), @id, kind
    static Key key_of(const Forwarded& f);
    std::map<Key, Forwarded> by_key_;
};

}  // namespace nclink::agent_detail
