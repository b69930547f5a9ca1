// The Prometheus text exposition format (version 0.0.4), written by hand: the
// few rules it has are kept here once, for the adapter, the agent and the
// bridge (docs/metrics.md).
//
//  - a family is `# HELP`, `# TYPE` and all its samples, together: samples
//    added in any order are grouped by family when rendered, so several
//    adapters of one process can share one exposition;
//  - label values escape `\`, `"` and line feeds; bytes that are no UTF-8
//    become '?' (the format is UTF-8);
//  - histograms are rendered cumulative with the `+Inf` bucket, `_sum` and
//    `_count`.
// Names are the caller's: `nclink_` prefix, `_total` on counters, base units
// (seconds, bytes) as Prometheus asks.
//
// Not synchronized: build one per scrape.
#pragma once

#include <nclink/traffic_stats.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nclink::core_detail {

using MetricLabels = std::vector<std::pair<std::string, std::string>>;

class PrometheusText {
public:
    /// A counter sample; `name` should end in `_total`.
    void counter(std::string_view name, std::string_view help, const MetricLabels& labels, std::uint64_t value);
    void counter(std::string_view name, std::string_view help, const MetricLabels& labels, double value);
    /// A gauge sample.
    void gauge(std::string_view name, std::string_view help, const MetricLabels& labels, double value);
    /// A histogram; `name` without the _bucket/_sum/_count suffixes.
    void histogram(std::string_view name, std::string_view help, const MetricLabels& labels, const HistogramSnapshot& histogram);
    /// Declares a family without samples yet (its HELP/TYPE are written even
    /// when no sample follows, e.g. a counter of a kind nothing happened to).
    void declare(std::string_view name, std::string_view type, std::string_view help);

    /// The exposition, families in the order first seen.
    std::string str() const;

    bool empty() const noexcept { return order_.empty(); }

private:
    struct Family {
        std::string type;
        std::string help;
        std::string samples;
    };
    Family& family(std::string_view name, std::string_view type, std::string_view help);

    std::vector<std::string> order_;
    std::map<std::string, Family, std::less<>> families_;
};

/// A label value as the format writes it (without the quotes).
std::string escape_label_value(std::string_view value);
/// A sample value: integers exactly, others shortest round-trip, +Inf/-Inf/NaN.
std::string format_metric_value(double value);

/// The content type of the text exposition.
inline constexpr std::string_view prometheus_content_type = "text/plain; version=0.0.4; charset=utf-8";

}  // namespace nclink::core_detail
