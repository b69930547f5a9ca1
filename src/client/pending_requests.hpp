// The requests of one client that wait for their response, keyed by "@id",
// with their deadlines. Internally synchronized: requests are added on the
// caller's thread and completed on the dispatch thread.
#pragma once

#include <nclink/error.hpp>
#include <nclink/topics.hpp>

#include <chrono>
#include <cstddef>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace nclink::client_detail {

using Clock = std::chrono::steady_clock;

/// Turns a response payload into the caller's answer. decode() and complete()
/// run on the dispatch thread; fail() runs on whichever thread took the request
/// out of the table (the dispatch thread, or a caller whose publish failed).
class Responder {
public:
    virtual ~Responder() = default;
    /// Decodes and keeps the response; false = malformed (the request stays pending).
    virtual bool decode(std::string_view payload) = 0;
    /// Hands what decode() kept to the caller.
    virtual void complete() = 0;
    virtual void fail(Error error) = 0;
};

struct PendingRequest {
    std::string id;
    TopicKind response_kind = TopicKind::query_response;
    Clock::time_point deadline;
    std::shared_ptr<Responder> responder;
    /// The terminal the request went to (its topic's dev), so a timeout can
    /// say what is known of it.
    std::string dev = {};
};

class PendingRequests {
public:
    /// false once closed (the client is stopping): the caller fails the request.
    bool add(PendingRequest request);
    /// The responder of a pending request, left in the table.
    std::shared_ptr<Responder> peek(const std::string& id, TopicKind* response_kind) const;
    /// Removes and returns a pending request.
    std::optional<PendingRequest> take(const std::string& id);
    /// Removes and returns every request whose deadline has passed; their ids
    /// are remembered (a bounded number) so a late response can be told apart.
    std::vector<PendingRequest> take_expired(Clock::time_point now);
    /// Removes everything and refuses further add()s.
    std::vector<PendingRequest> close();
    bool timed_out_recently(const std::string& id) const;
    std::optional<Clock::time_point> next_deadline() const;
    std::size_t size() const;

private:
    static constexpr std::size_t remembered_timeouts = 1024;

    mutable std::mutex mutex_;
    bool closed_ = false;
    std::unordered_map<std::string, PendingRequest> by_id_;
    std::multimap<Clock::time_point, std::string> by_deadline_;
    std::deque<std::string> timed_out_order_;
    std::unordered_set<std::string> timed_out_;
};

}  // namespace nclink::client_detail
