// The agent's picture of the terminals (agent_picture.hpp).
#include "agent/agent_picture.hpp"

#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

namespace nclink::agent_detail {

bool Picture::State::saw(const std::string& tid, Kind kind, Clock::Steady now, std::int64_t wall_s) {
    presence.set_kind(tid, kind);
    if (!presence.saw_dtu(tid, now, wall_s)) return false;
    saves.registry_changed();
    return true;
}

Message Picture::State::announce(const std::string& tid, Status status) {
    NotifyState notify;
    notify.tid = tid;
    notify.state = to_wire(status);
    ++expected_echo_[tid + "\n" + notify.state];
    return Message{topics::notify_state(tid), encode(notify), 1, true};
}

bool Picture::State::own_echo(const std::string& tid, const std::string& state) {
    const auto echo = expected_echo_.find(tid + "\n" + state);
    if (echo == expected_echo_.end()) return false;
    if (--echo->second == 0) expected_echo_.erase(echo);
    return true;
}

AgentState Picture::State::pair_state(const std::optional<std::string>& ex, const std::string& dev) const {
    if (!started_serving) return AgentState::initial;
    const bool app = !ex || presence.status(*ex) != Status::offline;
    return agent_state_of(app, presence.status(dev) != Status::offline);
}

std::string Picture::State::next_id(const std::string& agent_id, std::string_view what) {
    return agent_id + "-" + std::string(what) + "-" + std::to_string(++msg_counter_);
}

std::vector<TerminalInfo> Picture::State::terminals() const {
    std::set<std::string> ids;
    for (const auto& tid : presence.known()) ids.insert(tid);
    if (registrar)
        for (const auto& [tid, r] : registrar->all()) ids.insert(tid);
    std::vector<TerminalInfo> out;
    for (const auto& tid : ids) {
        TerminalInfo info;
        info.id = tid;
        info.kind = to_string(presence.kind(tid));
        info.registered = registrar && registrar->registered(tid);
        info.status = to_wire(presence.status(tid));
        info.last_alive_s = presence.last_alive_s(tid);
        if (const auto* cached = models.find(tid)) info.version = cached->version;
        out.push_back(std::move(info));
    }
    return out;
}

}  // namespace nclink::agent_detail
