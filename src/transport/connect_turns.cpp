#include "transport/connect_turns.hpp"

namespace nclink::transport_detail {

bool ConnectTurns::take(LoopMember* who) {
    if (limit_ == 0 || connecting_.count(who)) return true;
    if (connecting_.size() < limit_ && queued_.empty()) {
        connecting_.insert(who);
        return true;
    }
    if (queued_.insert(who).second) order_.push_back(who);
    return false;
}

LoopMember* ConnectTurns::release(LoopMember* who) {
    queued_.erase(who);  // left while waiting: its place in order_ is skipped
    if (connecting_.erase(who) == 0 && connecting_.size() >= limit_) return nullptr;
    while (!order_.empty() && connecting_.size() < limit_) {
        LoopMember* next = order_.front();
        order_.pop_front();
        if (queued_.erase(next) == 0) continue;
        connecting_.insert(next);
        return next;
    }
    return nullptr;
}

}  // namespace nclink::transport_detail
