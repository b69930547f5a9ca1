// Instances that split the work without $share ("instances" > 1,
// instance_split.hpp): every instance gets every request on its plain
// subscriptions and answers those of its share. A request of another share
// is not answered here, not counted and not watched for its adapter's answer
// (its owner does all that); it is still a DTU its sender published, so it
// counts as that sender's sign of life (3.22/3.23) here too: every instance
// then keeps the same liveness, online periods and Notify/State
// announcements as the one that answers, and any of them answers the next
// request of that terminal's share the same way.
#include "agent/agent_impl.hpp"

namespace nclink {

using namespace agent_detail;

bool Agent::Impl::answers_here(const ParsedTopic& topic, const Message& m) const {
    if (config.instances <= 1) return true;  // the broker's $share, or one instance: everything that arrives
    const auto owner = answering_instance(topic, m.payload, config.instances);
    return !owner || *owner == config.instance;
}

// The same signs of life the answering handlers take, under the same
// conditions (agent_terminals.cpp, agent_forwarding.cpp), and nothing else.
void Agent::Impl::watch_request(State& p, const ParsedTopic& topic, const Message& m, Out& out) {
    switch (topic.kind) {
        case TopicKind::register_request: {
            if (m.retained) return;
            auto request = decode<RegisterRequest>(m.payload);
            if (!request || !p.registrar->valid_id(request->cli_uuid)) return;
            p.presence.set_kind(request->cli_uuid, p.registrar->listed_kind(request->cli_uuid));
            alive(p, request->cli_uuid, Kind::unknown, out);
            return;
        }
        case TopicKind::discovery_request:
            if (!m.retained) alive(p, topic.ex.value_or(""), Kind::application, out);
            return;
        case TopicKind::probe_version: return alive(p, topic.dev, Kind::adapter, out);
        default:  // a request to an adapter
            if (m.retained || !topic.ex || *topic.ex == config.agent_id) return;
            return alive(p, *topic.ex, Kind::application, out);
    }
}

}  // namespace nclink
