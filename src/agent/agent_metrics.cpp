// DTUs by kind and the Prometheus text of the agent's statistics
// (docs/metrics.md lists every metric).
#include "agent/agent_metrics.hpp"

#include "agent/agent_impl.hpp"

#include <nclink/agent_metrics.hpp>

#include <map>

namespace nclink {

TrafficStats Agent::traffic_stats() const {
    TrafficStats t;
    t.dtus_in = impl_->dtus->in();
    t.dtus_out = impl_->dtus->out();
    return t;
}

namespace agent_detail {

void add_agent_metrics(core_detail::PrometheusText& out, const AgentStats& s, const std::vector<TerminalInfo>& terminals,
                       const TrafficStats& traffic) {
    using core_detail::MetricLabels;
    const MetricLabels none;
    const char* reg_help = "Register/Request handled, by outcome (8.2.2); repeated: a resend not answered again";
    out.counter("nclink_agent_registrations_total", reg_help, {{"outcome", "accepted"}}, s.registrations);
    out.counter("nclink_agent_registrations_total", reg_help, {{"outcome", "refused"}}, s.registrations_refused);
    out.counter("nclink_agent_registrations_total", reg_help, {{"outcome", "repeated"}}, s.registrations_repeated);
    out.counter("nclink_agent_discovery_answers_total", "Discovery/Request answered (8.2.3)", none, s.discoveries);
    out.counter("nclink_agent_version_checks_total", "Probe/Version answered (8.2.5)", none, s.versions);
    out.counter("nclink_agent_models_fetched_total", "Models fetched after a version change (8.2.7)", none, s.models_fetched);
    out.counter("nclink_agent_cached_probes_total", "Probe/Query answered from the cache for an offline adapter", none,
                s.cached_probes);
    const char* fwd_help = "Requests to adapters the agent answered itself, by reason (8.3.4, 8.3.5, table 19)";
    out.counter("nclink_agent_forward_failures_total", fwd_help, {{"reason", "unreachable"}}, s.unreachable);
    out.counter("nclink_agent_forward_failures_total", fwd_help, {{"reason", "timeout"}}, s.timeouts);
    out.counter("nclink_agent_forward_failures_total", fwd_help, {{"reason", "denied"}}, s.denied);
    out.gauge("nclink_agent_pending_requests", "Requests waiting for the adapter's answer now", none,
              static_cast<double>(s.pending));
    out.counter("nclink_agent_state_notifications_total", "Notify/State published by the agent (8.2.16)", none,
                s.state_notifications);
    out.counter("nclink_agent_malformed_dtus_total", "Undecodable DTUs", none, s.malformed);
    out.counter("nclink_agent_ignored_retained_total", "Requests ignored for their retain flag", none, s.ignored_retained);
    out.counter("nclink_agent_held_responses_total",
                "Responses for an offline application, kept by its persistent session (docs/delivery.md)", none, s.held_responses);

    // Every kind x status pair appears, zeros too, so a sum over time is continuous.
    std::map<std::pair<std::string, std::string>, std::uint64_t> by_state;
    std::map<std::string, std::uint64_t> registered;
    for (const char* kind : {"adapter", "application", "unknown"}) {
        for (const char* status : {"online", "offline", "unknown"}) by_state[{kind, status}] = 0;
        registered[kind] = 0;
    }
    for (const auto& t : terminals) {
        const std::string kind = t.kind.empty() ? "unknown" : t.kind;
        ++by_state[{kind, t.status.empty() ? "unknown" : t.status}];
        if (t.registered) ++registered[kind];
    }
    for (const auto& [key, n] : by_state)
        out.gauge("nclink_agent_terminals", "Terminals the agent knows, by kind and state (3.21-3.23)",
                  {{"kind", key.first}, {"state", key.second}}, static_cast<double>(n));
    for (const auto& [kind, n] : registered)
        out.gauge("nclink_agent_registered_terminals", "Terminals with an accepted registration, by kind", {{"kind", kind}},
                  static_cast<double>(n));

    out.declare("nclink_agent_dtus_received_total", "counter", "DTUs received, by topic kind");
    for (const auto& [kind, n] : traffic.dtus_in)
        out.counter("nclink_agent_dtus_received_total", "DTUs received, by topic kind", {{"kind", kind}}, n);
    out.declare("nclink_agent_dtus_sent_total", "counter", "DTUs published by the agent, by topic kind");
    for (const auto& [kind, n] : traffic.dtus_out)
        out.counter("nclink_agent_dtus_sent_total", "DTUs published by the agent, by topic kind", {{"kind", kind}}, n);

    const auto& t = s.transport;
    out.counter("nclink_agent_mqtt_connects_total", "Successful (re)connections to the broker", none, t.connects);
    out.gauge("nclink_agent_mqtt_buffered_messages", "Messages waiting to go to the broker", none, static_cast<double>(t.buffered));
    out.counter("nclink_agent_mqtt_dropped_messages_total", "Messages dropped because the offline buffer was full", none,
                t.dropped);
    out.counter("nclink_agent_mqtt_failovers_total",
                "Connections made to another broker of the failover list than the connection before", none, t.failovers);
    if (!t.broker.empty())
        out.gauge("nclink_agent_mqtt_broker", "1 for the broker connected to, or tried next while the link is down",
                  {{"broker", t.broker}}, 1);
}

}  // namespace agent_detail

std::string prometheus_metrics(const Agent& agent) {
    core_detail::PrometheusText out;
    agent_detail::add_agent_metrics(out, agent.stats(), agent.terminals(), agent.traffic_stats());
    return out.str();
}

}  // namespace nclink
