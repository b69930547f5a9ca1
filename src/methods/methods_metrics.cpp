// The methods feature's metrics (methods_metrics.hpp).
#include "methods/methods_metrics.hpp"

namespace nclink::detail {

void add_methods_metrics(PrometheusText& out, const FeatureMetricsInput& in) {
    const Json& methods = in.stats;
    if (!methods.is_object()) return;
    const MetricLabels& d = in.device;
    out.gauge("nclink_adapter_methods_running", "Method calls running now", d,
              static_cast<double>(json_count(methods, "running")));
    out.counter("nclink_adapter_method_calls_total", "Method/Call requests accepted (8.2.22)", d, json_count(methods, "accepted"));
    out.counter("nclink_adapter_method_calls_refused_total", "Method/Call requests refused (malformed, unknown, busy)", d,
                json_count(methods, "rejected_calls"));
    const char* results_help = "Method/Result DTUs by result (8.2.24)";
    for (const auto& [result, key] :
         {std::pair<const char*, const char*>{"finished", "finished"}, {"canceled", "canceled"}, {"error", "errors"}}) {
        MetricLabels l = d;
        l.emplace_back("result", result);
        out.counter("nclink_adapter_method_results_total", results_help, l, json_count(methods, key));
    }
}

}  // namespace nclink::detail
