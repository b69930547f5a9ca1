#include "http/http_metrics.hpp"

namespace nclink::http {

void HttpMetrics::observe(const RequestRecord& record) {
    // A stream's time is its start; its length says nothing about the server.
    std::lock_guard<std::mutex> lock(mutex_);
    ++requests_[{std::string(record.method), std::string(record.route), record.status}];
    if (record.stream) return;
    auto& histogram = latency_[std::string(record.route)];
    if (!histogram) histogram = std::make_unique<core_detail::LatencyHistogram>();
    histogram->observe(record.elapsed);
}

void HttpMetrics::render(core_detail::PrometheusText& out, const std::string& prefix) const {
    const std::string requests = prefix + "_http_requests_total";
    const std::string duration = prefix + "_http_request_duration_seconds";
    const char* requests_help = "HTTP requests answered, by method, route pattern and status code";
    const char* duration_help = "HTTP requests from receipt to the answer (streams: to their start), by route pattern";
    out.declare(requests, "counter", requests_help);
    out.declare(duration, "histogram", duration_help);
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [key, n] : requests_)
        out.counter(requests, requests_help,
                    {{"method", std::get<0>(key)}, {"route", std::get<1>(key)}, {"code", std::to_string(std::get<2>(key))}}, n);
    for (const auto& [route, histogram] : latency_)
        out.histogram(duration, duration_help, {{"route", route}}, histogram->snapshot());
}

void HttpMetrics::render(core_detail::PrometheusText& out, const std::string& prefix, const ConnectionCounters& c) {
    // What the connection gate did with slow, idle and surplus clients
    // (docs/bridge.md "Slow and idle clients"): the counters say whether the
    // limits bite, and which.
    out.counter(prefix + "_http_connections_accepted_total", "HTTP connections accepted", {}, c.accepted);
    const std::string refused = prefix + "_http_connections_refused_total";
    const char* refused_help = "HTTP connections closed at once because a connection cap was reached, by cap";
    out.counter(refused, refused_help, {{"cap", "total"}}, c.refused_total);
    out.counter(refused, refused_help, {{"cap", "per_peer"}}, c.refused_per_peer);
    const std::string closed = prefix + "_http_connections_closed_total";
    const char* closed_help = "HTTP connections the server closed for a deadline, by reason";
    out.counter(closed, closed_help, {{"reason", "header_timeout"}}, c.header_timeouts);
    out.counter(closed, closed_help, {{"reason", "idle"}}, c.idle_closed);
    out.gauge(prefix + "_http_connections_open", "HTTP connections open now", {}, static_cast<double>(c.open));
    out.gauge(prefix + "_http_connections_waiting",
              "HTTP connections open now that wait for a whole request head, without a worker", {}, static_cast<double>(c.waiting));
    out.counter(prefix + "_http_streams_total", "Streaming answers begun (SSE, MTConnect interval=)", {}, c.streams_started);
    out.counter(prefix + "_http_streams_refused_total", "Streaming answers refused with 503: the stream cap was reached", {},
                c.streams_refused);
    out.gauge(prefix + "_http_streams", "Streaming answers running now", {}, static_cast<double>(c.streams));
}

}  // namespace nclink::http
