// The methods feature's metrics (methods_metrics.hpp).
#include "methods/methods_metrics.hpp"

namespace nclink::methods_detail {

void add_methods_metrics(core_detail::PrometheusText& out, const feature_detail::FeatureMetricsInput& in) {
    const Json& methods = in.stats;
    if (!methods.is_object()) return;
    const core_detail::MetricLabels& d = in.device;
    out.gauge("nclink_adapter_methods_running", "Method calls running now", d,
              static_cast<double>(feature_detail::json_count(methods, "running")));
    out.counter("nclink_adapter_method_calls_total", "Method/Call requests accepted (8.2.22)", d,
                feature_detail::json_count(methods, "accepted"));
    out.counter("nclink_adapter_method_calls_refused_total", "Method/Call requests refused (malformed, unknown, busy)", d,
                feature_detail::json_count(methods, "rejected_calls"));
    const char* results_help = "Method/Result DTUs by result (8.2.24)";
    for (const auto& [result, key] :
         {std::pair<const char*, const char*>{"finished", "finished"}, {"canceled", "canceled"}, {"error", "errors"}}) {
        core_detail::MetricLabels l = d;
        l.emplace_back("result", result);
        out.counter("nclink_adapter_method_results_total", results_help, l, feature_detail::json_count(methods, key));
    }
}

}  // namespace nclink::methods_detail
