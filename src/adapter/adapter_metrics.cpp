// Traffic counters of the adapter and the Prometheus text of its statistics
// (docs/metrics.md lists every metric).
#include "adapter/adapter_metrics.hpp"

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

namespace detail {
namespace {

std::uint64_t json_count(const Json& object, const char* key) {
    if (!object.is_object()) return 0;
    auto it = object.find(key);
    if (it == object.end() || !it->is_number()) return 0;
    return it->is_number_unsigned() ? it->get<std::uint64_t>()
                                    : static_cast<std::uint64_t>(std::max<double>(0, it->get<double>()));
}

const Json& member(const Json& object, const char* key) {
    static const Json none;
    if (!object.is_object()) return none;
    auto it = object.find(key);
    return it == object.end() ? none : *it;
}

// ChannelStats::lateness in Prometheus form: bounds in seconds.
HistogramSnapshot lateness_histogram(const ChannelStats& c) {
    HistogramSnapshot h;
    for (auto bound_us : kLatenessBoundsUs) h.upper_bounds.push_back(static_cast<double>(bound_us) / 1e6);
    h.counts.assign(c.lateness.begin(), c.lateness.end());
    for (auto n : h.counts) h.count += n;
    // The channel keeps no sum of lateness; each tick is counted at its
    // bucket's lower bound, so rate(_sum)/rate(_count) is a lower bound of
    // the mean (docs/metrics.md).
    for (std::size_t i = 1; i < h.counts.size(); ++i) h.sum += static_cast<double>(h.counts[i]) * h.upper_bounds[i - 1];
    return h;
}

}  // namespace

void add_adapter_metrics(PrometheusText& out, const std::string& dev, const AdapterStats& s, const SamplingStats& sampling,
                         const TrafficStats& traffic) {
    const MetricLabels d{{"dev", dev}};
    auto with = [&](const char* name, std::string value) {
        MetricLabels l = d;
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
                "Driver values refused for breaking their item's chapter-7 rule (docs/porting-guide.md)", d,
                s.values_refused);
    out.counter("nclink_adapter_applications_released_total",
                "Applications judged offline (3.22) whose events and dynamic channels were released", d,
                s.applications_released);
    out.declare("nclink_adapter_request_duration_seconds", "histogram",
                "Requests from receipt to the answer (Method/Call: to its acceptance), by request kind");
    for (const auto& [kind, h] : traffic.request_seconds)
        out.histogram("nclink_adapter_request_duration_seconds",
                      "Requests from receipt to the answer (Method/Call: to its acceptance), by request kind",
                      with("kind", kind), h);

    // ---- DTUs by kind
    out.declare("nclink_adapter_dtus_received_total", "counter", "DTUs received, by topic kind");
    for (const auto& [kind, n] : traffic.dtus_in)
        out.counter("nclink_adapter_dtus_received_total", "DTUs received, by topic kind", with("kind", kind), n);
    out.declare("nclink_adapter_dtus_sent_total", "counter", "DTUs handed to the MQTT connection, by topic kind");
    for (const auto& [kind, n] : traffic.dtus_out)
        out.counter("nclink_adapter_dtus_sent_total", "DTUs handed to the MQTT connection, by topic kind",
                    with("kind", kind), n);

    // ---- MQTT
    const auto& t = s.transport;
    out.counter("nclink_adapter_mqtt_connects_total", "Successful (re)connections to the broker", d, t.connects);
    out.gauge("nclink_adapter_mqtt_buffered_messages", "Messages waiting to go to the broker", d,
              static_cast<double>(t.buffered));
    out.gauge("nclink_adapter_mqtt_buffered_bytes", "Bytes of the messages waiting to go to the broker", d,
              static_cast<double>(t.buffered_bytes));
    out.gauge("nclink_adapter_mqtt_in_flight_messages", "Messages handed to the broker, not yet acknowledged", d,
              static_cast<double>(t.in_flight));
    out.counter("nclink_adapter_mqtt_dropped_bytes_total", "Bytes of messages dropped because the offline buffer was full",
                d, t.dropped_bytes);
    out.counter("nclink_adapter_mqtt_stalled_links_total",
                "Connections dropped and made again because nothing in flight was acknowledged within the ack timeout",
                d, t.stalled_links);

    // ---- drops by cause (each in its own unit: see docs/metrics.md)
    const Json& sampling_json = member(s.features, "sampling");
    const Json& spool = member(sampling_json, "spool");
    const Json& events = member(s.features, "events");
    std::uint64_t ring_drops = 0;
    for (const auto& c : sampling.channels) ring_drops += c.drops;
    const char* drops_help =
        "Data lost, by cause: outbox_full (MQTT messages), ring_full (sample rows), spool_full (Sample DTUs), "
        "event_inbox_full (values notified for events)";
    out.counter("nclink_adapter_drops_total", drops_help, with("cause", "outbox_full"), t.dropped);
    out.counter("nclink_adapter_drops_total", drops_help, with("cause", "ring_full"), ring_drops);
    out.counter("nclink_adapter_drops_total", drops_help, with("cause", "spool_full"), json_count(spool, "dropped"));
    out.counter("nclink_adapter_drops_total", drops_help, with("cause", "event_inbox_full"),
                json_count(events, "dropped_values"));

    // ---- store and forward
    out.gauge("nclink_adapter_spool_dtus", "Sample DTUs held while the broker was unreachable (RAM and disk)", d,
              static_cast<double>(json_count(spool, "pending")));
    out.gauge("nclink_adapter_spool_memory_bytes", "Bytes of spooled Sample DTUs in memory", d,
              static_cast<double>(json_count(spool, "memory_bytes")));
    out.gauge("nclink_adapter_spool_disk_bytes", "Bytes of spooled Sample DTUs on disk", d,
              static_cast<double>(json_count(spool, "disk_bytes")));
    out.counter("nclink_adapter_spool_replayed_total", "Spooled Sample DTUs sent after the link came back", d,
                json_count(spool, "replayed"));

    // ---- sampling, per channel
    out.gauge("nclink_adapter_sampling_running", "1 while the sample channels run", d, sampling.running ? 1 : 0);
    for (const auto& c : sampling.channels) {
        MetricLabels l = d;
        l.emplace_back("channel", c.id);
        out.gauge("nclink_adapter_sampling_interval_seconds", "The channel's sampleInterval", l, c.sample_interval_ms / 1e3);
        out.counter("nclink_adapter_sampling_rows_total", "Rows sampled into the channel's ring (rows of missed ticks too)",
                    l, c.rows_sampled);
        out.counter("nclink_adapter_sampling_rows_published_total", "Rows handed to the transport in Sample DTUs", l,
                    c.rows_published);
        out.counter("nclink_adapter_sampling_dtus_total", "Sample DTUs published by the channel", l, c.dtus_published);
        out.counter("nclink_adapter_sampling_overruns_total", "Ticks whose read could not start before the next was due",
                    l, c.overruns);
        out.counter("nclink_adapter_sampling_skipped_ticks_total", "Ticks not produced at all after a long stall", l,
                    c.skipped_ticks);
        out.counter("nclink_adapter_sampling_null_values_total", "Values sent as null (failed reads, missed ticks)", l,
                    c.null_values);
        out.gauge("nclink_adapter_sampling_max_lateness_seconds", "Largest lateness of a tick so far", l,
                  static_cast<double>(c.max_lateness_us) / 1e6);
        out.histogram("nclink_adapter_sampling_lateness_seconds",
                      "How late each tick's pass started after its deadline (buckets count lateness below le)", l,
                      lateness_histogram(c));
    }
    const Json& dynamic = member(sampling_json, "dynamic");
    if (dynamic.is_object())
        out.gauge("nclink_adapter_dynamic_channels", "Dynamic sample channels registered by applications (8.2.17)", d,
                  static_cast<double>(json_count(dynamic, "channels")));

    // ---- events and methods
    if (events.is_object()) {
        out.gauge("nclink_adapter_events_registered", "Event registrations in place (8.2.27)", d,
                  static_cast<double>(json_count(events, "registered")));
        out.counter("nclink_adapter_events_fired_total", "Event DTUs triggered (8.2.31)", d, json_count(events, "fired"));
    }
    const Json& methods = member(s.features, "methods");
    if (methods.is_object()) {
        out.gauge("nclink_adapter_methods_running", "Method calls running now", d,
                  static_cast<double>(json_count(methods, "running")));
        out.counter("nclink_adapter_method_calls_total", "Method/Call requests accepted (8.2.22)", d,
                    json_count(methods, "accepted"));
        out.counter("nclink_adapter_method_calls_refused_total", "Method/Call requests refused (malformed, unknown, busy)",
                    d, json_count(methods, "rejected_calls"));
        const char* results_help = "Method/Result DTUs by result (8.2.24)";
        out.counter("nclink_adapter_method_results_total", results_help, with("result", "finished"),
                    json_count(methods, "finished"));
        out.counter("nclink_adapter_method_results_total", results_help, with("result", "canceled"),
                    json_count(methods, "canceled"));
        out.counter("nclink_adapter_method_results_total", results_help, with("result", "error"),
                    json_count(methods, "errors"));
    }
}

}  // namespace detail

std::string prometheus_metrics(const std::vector<const Adapter*>& adapters) {
    detail::PrometheusText out;
    for (const Adapter* a : adapters) {
        if (!a) continue;
        detail::add_adapter_metrics(out, a->dev_uuid(), a->stats(), a->sampling_stats(), a->traffic_stats());
    }
    return out.str();
}

std::string prometheus_metrics(const Adapter& adapter) { return prometheus_metrics(std::vector<const Adapter*>{&adapter}); }

}  // namespace nclink
