// Metrics of an HttpServer's answers, for the program's /metrics
// (docs/metrics.md): requests by method, route and status code, and a latency
// histogram by route. Install observer() with HttpServer::set_observer().
//
// Thread-safety: observe() from any worker thread; render() from any thread.
// Routes are the patterns the program added, so the label sets stay bounded
// whatever paths clients ask for (unmatched requests count under route "").
#pragma once

#include "core/latency_histogram.hpp"
#include "core/prometheus_text.hpp"
#include "http/http_server.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>

namespace nclink::http {

class HttpMetrics {
public:
    void observe(const RequestRecord& record);
    /// An observer for HttpServer::set_observer; `this` must outlive the server.
    RequestObserver observer() {
        return [this](const RequestRecord& r) { observe(r); };
    }
    /// Adds `<prefix>_http_requests_total` and
    /// `<prefix>_http_request_duration_seconds` (e.g. prefix "nclink_bridge").
    void render(core_detail::PrometheusText& out, const std::string& prefix) const;
    /// Adds the server's connection counters (HttpServer::connection_counters()):
    /// `<prefix>_http_connections_accepted_total`,
    /// `<prefix>_http_connections_refused_total{cap="total"|"per_peer"}`,
    /// `<prefix>_http_connections_closed_total{reason="header_timeout"|"idle"}`,
    /// `<prefix>_http_connections_open`, `<prefix>_http_connections_waiting`,
    /// `<prefix>_http_streams_total`, `<prefix>_http_streams_refused_total` and
    /// `<prefix>_http_streams`. Static: the counters are the server's.
    static void render(core_detail::PrometheusText& out, const std::string& prefix, const ConnectionCounters& counters);

private:
    mutable std::mutex mutex_;
    std::map<std::tuple<std::string, std::string, int>, std::uint64_t> requests_;    // method, route, status
    std::map<std::string, std::unique_ptr<core_detail::LatencyHistogram>> latency_;  // route
};

}  // namespace nclink::http
