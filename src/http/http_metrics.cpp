#include "http/http_metrics.hpp"

namespace nclink::http {

void HttpMetrics::observe(const RequestRecord& record) {
    // A stream's time is its start; its length says nothing about the server.
    std::lock_guard<std::mutex> lock(mutex_);
    ++requests_[{std::string(record.method), std::string(record.route), record.status}];
    if (record.stream) return;
    auto& histogram = latency_[std::string(record.route)];
    if (!histogram) histogram = std::make_unique<detail::LatencyHistogram>();
    histogram->observe(record.elapsed);
}

void HttpMetrics::render(detail::PrometheusText& out, const std::string& prefix) const {
    const std::string requests = prefix + "_http_requests_total";
    const std::string duration = prefix + "_http_request_duration_seconds";
    const char* requests_help = "HTTP requests answered, by method, route pattern and status code";
    const char* duration_help = "HTTP requests from receipt to the answer (streams: to their start), by route pattern";
    out.declare(requests, "counter", requests_help);
    out.declare(duration, "histogram", duration_help);
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [key, n] : requests_)
        out.counter(requests, requests_help,
                    {{"method", std::get<0>(key)}, {"route", std::get<1>(key)}, {"code", std::to_string(std::get<2>(key))}},
                    n);
    for (const auto& [route, histogram] : latency_)
        out.histogram(duration, duration_help, {{"route", route}}, histogram->snapshot());
}

}  // namespace nclink::http
