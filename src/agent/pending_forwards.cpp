#include "agent/pending_forwards.hpp"

#include "agent/registrar.hpp"  // id_text

namespace nclink::agent_detail {

PendingForwards::Key PendingForwards::key_of(const Forwarded& f) {
    return {f.dev, f.ex.value_or(""), id_text(f.msg_id), static_cast<int>(f.kind)};
}

void PendingForwards::add(Forwarded request) {
    if (!request.msg_id) return;
    auto key = key_of(request);
    by_key_.emplace(std::move(key), std::move(request));  // a repeated request keeps its first deadline
}

bool PendingForwards::answered(TopicKind answer_kind, const std::string& dev, const std::optional<std::string>& ex,
                               const std::string& id) {
    bool any = false;
    for (TopicKind request :
         {TopicKind::probe_query_request, TopicKind::probe_set_request, TopicKind::query_request, TopicKind::set_request,
          TopicKind::sample_register_request, TopicKind::sample_unregister_request, TopicKind::method_call,
          TopicKind::method_control_request, TopicKind::event_register_request, TopicKind::event_unregister_request}) {
        // A method call is answered by its first Method/Status as well as its result.
        const bool matches = response_kind(request) == answer_kind ||
                             (request == TopicKind::method_call && answer_kind == TopicKind::method_status);
        if (!matches) continue;
        any = by_key_.erase(Key{dev, ex.value_or(""), id, static_cast<int>(request)}) > 0 || any;
    }
    return any;
}

std::vector<Forwarded> PendingForwards::take_expired(Clock::Steady now) {
    std::vector<Forwarded> out;
    for (auto it = by_key_.begin(); it != by_key_.end();) {
        if (now >= it->second.deadline) {
            out.push_back(std::move(it->second));
            it = by_key_.erase(it);
        } else {
            ++it;
        }
    }
    return out;
}

std::vector<Forwarded> PendingForwards::take_for(const std::string& dev) {
    std::vector<Forwarded> out;
    for (auto it = by_key_.begin(); it != by_key_.end();) {
        if (it->second.dev == dev) {
            out.push_back(std::move(it->second));
            it = by_key_.erase(it);
        } else {
            ++it;
        }
    }
    return out;
}

}  // namespace nclink::agent_detail
