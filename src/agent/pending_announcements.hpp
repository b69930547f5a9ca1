// Online announcements the agent holds back. The agent takes Sample DTUs at
// QoS 0 (agent.cpp), and mosquitto passes a QoS 0 message to a subscriber at
// once while its QoS 1 messages wait for the subscriber's window: a
// machine's first Sample DTU can reach the agent before that machine's own
// Notify/State "online" (8.2.16), many seconds before it when thousands of
// machines start together. Announcing "online" for it then (alive(), 3.22)
// says what the machine is about to say itself, on the agent's busiest
// connection. So a terminal that a Sample DTU brings online is online in
// the agent's picture at once, but its announcement waits `grace`; any
// Notify/State of it meanwhile cancels it. Pure bookkeeping: no clock, no lock.
#pragma once

#include <nclink/clock.hpp>

#include <deque>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace nclink::agent_detail {

class PendingAnnouncements {
public:
    /// `tid` came online at `now` by a Sample DTU: announce it at now + grace
    /// unless cancelled. A terminal already waiting keeps its first time.
    void hold(const std::string& tid, Clock::Steady now, std::chrono::milliseconds grace);
    /// A Notify/State of `tid` arrived, or it went offline: no announcement.
    void cancel(const std::string& tid) { due_.erase(tid); }
    /// The terminals whose time came by `now`, oldest first; forgotten.
    std::vector<std::string> take_due(Clock::Steady now);
    std::size_t size() const { return due_.size(); }

private:
    // One grace for all, so the queue is in order of due time; a cancelled
    // or re-held terminal leaves a stale entry that take_due() skips.
    std::deque<std::pair<Clock::Steady, std::string>> queue_;
    std::unordered_map<std::string, Clock::Steady> due_;
};

}  // namespace nclink::agent_detail
