// The sampling feature's metrics (sampling_metrics.hpp).
#include "sampling/sampling_metrics.hpp"

namespace nclink::sampling_detail {
namespace {

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

void add_sampling_metrics(core_detail::PrometheusText& out, const feature_detail::FeatureMetricsInput& in,
                          const SamplingStats& channels) {
    const core_detail::MetricLabels& d = in.device;
    const Json& spool = feature_detail::json_member(in.stats, "spool");
    std::uint64_t ring_drops = 0;
    for (const auto& c : channels.channels) ring_drops += c.drops;
    feature_detail::add_drop_metric(out, d, "ring_full", ring_drops);
    feature_detail::add_drop_metric(out, d, "spool_full", feature_detail::json_count(spool, "dropped"));

    // ---- store and forward
    out.gauge("nclink_adapter_spool_dtus", "Sample DTUs held while the broker was unreachable (RAM and disk)", d,
              static_cast<double>(feature_detail::json_count(spool, "pending")));
    out.gauge("nclink_adapter_spool_memory_bytes", "Bytes of spooled Sample DTUs in memory", d,
              static_cast<double>(feature_detail::json_count(spool, "memory_bytes")));
    out.gauge("nclink_adapter_spool_disk_bytes", "Bytes of spooled Sample DTUs on disk", d,
              static_cast<double>(feature_detail::json_count(spool, "disk_bytes")));
    out.counter("nclink_adapter_spool_replayed_total", "Spooled Sample DTUs sent after the link came back", d,
                feature_detail::json_count(spool, "replayed"));

    // ---- per channel
    out.gauge("nclink_adapter_sampling_running", "1 while the sample channels run", d, channels.running ? 1 : 0);
    for (const auto& c : channels.channels) {
        core_detail::MetricLabels l = d;
        l.emplace_back("channel", c.id);
        out.gauge("nclink_adapter_sampling_interval_seconds", "The channel's sampleInterval", l, c.sample_interval_ms / 1e3);
        out.counter("nclink_adapter_sampling_rows_total", "Rows sampled into the channel's ring (rows of missed ticks too)", l,
                    c.rows_sampled);
        out.counter("nclink_adapter_sampling_rows_published_total", "Rows handed to the transport in Sample DTUs", l,
                    c.rows_published);
        out.counter("nclink_adapter_sampling_dtus_total", "Sample DTUs published by the channel", l, c.dtus_published);
        out.counter("nclink_adapter_sampling_overruns_total", "Ticks whose read could not start before the next was due", l,
                    c.overruns);
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
    const Json& dynamic = feature_detail::json_member(in.stats, "dynamic");
    if (dynamic.is_object())
        out.gauge("nclink_adapter_dynamic_channels", "Dynamic sample channels registered by applications (8.2.17)", d,
                  static_cast<double>(feature_detail::json_count(dynamic, "channels")));
}

}  // namespace nclink::sampling_detail
