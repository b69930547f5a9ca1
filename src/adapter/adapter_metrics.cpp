// Traffic counters of the adapter and the Prometheus text of its statistics
// (docs/metrics.md lists every metric).
#include "adapter/adapter_metrics.hpp"

#include "adapter/adapter_features.hpp"
#include "adapter/adapter_impl.hpp"

#include <nclink/adapter_metrics.hpp>

namespace nclink {

TrafficStats Adapter::traffic_stats() const {
    TrafficStats t;
    t.dtus_in = impl_->dtus->in();
    t.dtus_out = impl_->dtus->out();
    if (impl_->composed.load(std::memory_order_acquire)) impl_->requests->add_latency(t);
    return t;
}

namespace adapter_detail {

void add_adapter_metrics(core_detail::PrometheusText& out, const std::string& dev, const AdapterStats& s,
                         const SamplingStats& sampling, const TrafficStats& traffic) {
    const core_detail::MetricLabels d{{"dev", dev}};
    auto with = [&](const char* name, std::string value) {
        core_detail::MetricLabels l = d;
        l.emplace_back(name, std::move(value));
        return l;
    };

    // ---- the terminal
    for (auto state : {AdapterState::initial, AdapterState::normal, AdapterState::request, AdapterState::disconnected})
        out.gauge("nclink_adapter_state", "1 for the adapter's current state, 0 for the others",
                  with("state", std::string(to_string(state))), s.state == state ? 1 : 0);
    out.gauge("nclink_adapter_registered", "1 when an agent accepted the adapter's Register/Request (8.2.2)", d,
              s.registered ? 1 : 0);

    // ---- requests
    out.counter("nclink_adapter_requests_total", "Request DTUs handled", d, s.requests);
    out.counter("nclink_adapter_requests_ignored_total", "Requests ignored: retained, or a repeated @id",
                with("reason", "retained"), s.ignored_retained);
    out.counter("nclink_adapter_requests_ignored_total", "Requests ignored: retained, or a repeated @id",
                with("reason", "duplicate"), s.ignored_duplicates);
    out.counter("nclink_adapter_requests_malformed_total", "Requests answered NG as a whole (undecodable)", d, s.rejected);
    out.counter("nclink_adapter_driver_timeouts_total", "Driver calls past their deadline", d, s.driver_timeouts);
    out.counter("nclink_adapter_values_refused_total",
                "Driver values refused for breaking their item's chapter-7 rule (docs/porting-guide.md)", d, s.values_refused);
    out.counter("nclink_adapter_applications_released_total",
                "Applications judged offline (3.22) whose events and dynamic channels were released", d, s.applications_released);
    out.declare("nclink_adapter_request_duration_seconds", "histogram",
                "Requests from receipt to the answer (Method/Call: to its acceptance), by request kind");
    for (const auto& [kind, h] : traffic.request_seconds)
        out.histogram("nclink_adapter_request_duration_seconds",
                      "Requests from receipt to the answer (Method/Call: to its acceptance), by request kind", with("kind", kind),
                      h);

    // ---- DTUs by kind
    out.declare("nclink_adapter_dtus_received_total", "counter", "DTUs received, by topic kind");
    for (const auto& [kind, n] : traffic.dtus_in)
        out.counter("nclink_adapter_dtus_received_total", "DTUs received, by topic kind", with("kind", kind), n);
    out.declare("nclink_adapter_dtus_sent_total", "counter", "DTUs handed to the MQTT connection, by topic kind");
    for (const auto& [kind, n] : traffic.dtus_out)
        out.counter("nclink_adapter_dtus_sent_total", "DTUs handed to the MQTT connection, by topic kind", with("kind", kind), n);

    // ---- MQTT
    const auto& t = s.transport;
    out.counter("nclink_adapter_mqtt_connects_total", "Successful (re)connections to the broker", d, t.connects);
    out.gauge("nclink_adapter_mqtt_buffered_messages", "Messages waiting to go to the broker", d, static_cast<double>(t.buffered));
    out.gauge("nclink_adapter_mqtt_buffered_bytes", "Bytes of the messages waiting to go to the broker", d,
              static_cast<double>(t.buffered_bytes));
    out.gauge("nclink_adapter_mqtt_in_flight_messages", "Messages handed to the broker, not yet acknowledged", d,
              static_cast<double>(t.in_flight));
    out.counter("nclink_adapter_mqtt_dropped_bytes_total", "Bytes of messages dropped because the offline buffer was full", d,
                t.dropped_bytes);
    out.counter("nclink_adapter_mqtt_stalled_links_total",
                "Connections dropped and made again because nothing in flight was acknowledged within the ack timeout", d,
                t.stalled_links);
    out.counter("nclink_adapter_mqtt_failovers_total",
                "Connections made to another broker of the failover list than the connection before", d, t.failovers);
    if (!t.broker.empty())
        out.gauge("nclink_adapter_mqtt_broker", "1 for the broker connected to, or tried next while the link is down",
                  with("broker", t.broker), 1);

    // ---- drops by cause (each in its own unit: see docs/metrics.md); the
    // features add theirs with their own families (adapter_features.hpp)
    feature_detail::add_drop_metric(out, d, "outbox_full", t.dropped);
    feature_metrics_from_stats(out, d, s.features, sampling);
}

}  // namespace adapter_detail

std::string prometheus_metrics(const std::vector<const Adapter*>& adapters) {
    core_detail::PrometheusText out;
    for (const Adapter* a : adapters) {
        if (!a) continue;
        adapter_detail::add_adapter_metrics(out, a->dev_uuid(), a->stats(), a->sampling_stats(), a->traffic_stats());
    }
    return out.str();
}

std::string prometheus_metrics(const Adapter& adapter) { return prometheus_metrics(std::vector<const Adapter*>{&adapter}); }

}  // namespace nclink
