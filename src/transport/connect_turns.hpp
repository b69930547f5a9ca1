// Turns to connect among the connections of one MQTT loop (a gateway's
// machines): at most `limit` wait for their CONNACK at once, the others
// queue in the order they asked. When 5,000 machines of a gateway sent their
// CONNECTs together, the broker answered thousands of them after their
// 5 s connect timeout; each then connected again from the start, and the
// start took 8-29 s instead of the few seconds the broker needs for them in
// turn (docs/performance.md). No locking: the loop's thread only.
#pragma once

#include <cstddef>
#include <deque>
#include <unordered_set>

namespace nclink::transport_detail {

class LoopMember;

class ConnectTurns {
public:
    /// `limit` 0: no limit (every connection goes at once).
    explicit ConnectTurns(std::size_t limit) : limit_(limit) {}

    /// True when `who` may send its CONNECT now (also when it was given the
    /// turn while it waited). False: it waits in the queue; release() names
    /// it when its turn comes.
    bool take(LoopMember* who);
    /// `who`'s attempt ended (CONNACK, failure, a dropped connection) or it
    /// left the loop. Returns the member whose turn it is now, or nullptr;
    /// the caller wakes it. Harmless for a member that holds no turn.
    LoopMember* release(LoopMember* who);

    std::size_t connecting() const { return connecting_.size(); }
    std::size_t waiting() const { return queued_.size(); }

private:
    const std::size_t limit_;
    std::unordered_set<LoopMember*> connecting_;  // hold a turn
    std::deque<LoopMember*> order_;               // asked, oldest first; may hold members that left
    std::unordered_set<LoopMember*> queued_;      // in order_ and still waiting
};

}  // namespace nclink::transport_detail
