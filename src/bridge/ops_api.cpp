#include "bridge/ops_api.hpp"

#include "core/prometheus_text.hpp"

#include <map>
#include <string_view>

namespace nclink::bridge {

extern const std::string_view kDashboardPage;  // src/bridge/dashboard/index.html, compiled in

namespace {

struct Fleet {
    std::map<std::string, std::size_t> by_state{{"online", 0}, {"offline", 0}, {"unknown", 0}};
    std::size_t devices = 0;
    std::size_t buffered = 0;
    std::uint64_t last_sequence = 0;
};

Fleet fleet(const BridgeStore& store) {
    return store.read([](const BridgeState& st) {
        Fleet f;
        f.devices = st.devices.size();
        for (const auto& d : st.devices) ++f.by_state[d.state];
        f.buffered = st.buffer.size();
        f.last_sequence = st.buffer.last_sequence();
        return f;
    });
}

}  // namespace

Json OpsApi::health() const {
    const Fleet f = fleet(store_);
    const auto stats = client_.stats();
    return Json{{"broker", std::string(to_string(client_.link_state()))},
                {"devices", f.devices},
                {"devices_online", f.by_state.at("online")},
                {"observations", f.buffered},
                {"buffer_size", store_.buffer_size()},
                {"streams", server_.active_streams()},
                {"pending_requests", client_.pending_requests()},
                {"request_timeouts", stats.timeouts},
                {"uptime_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count()}};
}

std::string OpsApi::metrics() const {
    core_detail::PrometheusText out;
    const Fleet f = fleet(store_);
    for (const auto& [state, n] : f.by_state)
        out.gauge("nclink_bridge_devices", "Devices the bridge follows, by state (8.2.16)", {{"state", state}},
                  static_cast<double>(n));
    out.gauge("nclink_bridge_mqtt_connected", "1 while the bridge's MQTT link is up", {},
              client_.link_state() == LinkState::connected ? 1 : 0);
    out.counter("nclink_bridge_observations_total", "Observations recorded (the last MTConnect sequence)", {}, f.last_sequence);
    out.gauge("nclink_bridge_buffer_observations", "Observations held in the MTConnect buffer", {},
              static_cast<double>(f.buffered));
    out.gauge("nclink_bridge_buffer_capacity_observations", "The MTConnect bufferSize", {},
              static_cast<double>(store_.buffer_size()));
    out.gauge("nclink_bridge_pending_requests", "NC-Link requests waiting for their answer", {},
              static_cast<double>(client_.pending_requests()));

    // The client's counters, by the DTU kinds they count (docs/metrics.md).
    const auto s = client_.stats();
    const char* in_help = "DTUs received by the bridge's client, by kind";
    out.counter("nclink_bridge_dtus_received_total", in_help, {{"kind", "response"}}, s.responses);
    out.counter("nclink_bridge_dtus_received_total", in_help, {{"kind", "sample"}}, s.samples);
    out.counter("nclink_bridge_dtus_received_total", in_help, {{"kind", "event"}}, s.events);
    out.counter("nclink_bridge_dtus_received_total", in_help, {{"kind", "notification"}}, s.notifications);
    out.counter("nclink_bridge_dtus_sent_total", "Request DTUs the bridge's client published", {{"kind", "request"}}, s.requests);
    const char* drop_help = "DTUs the bridge's client dropped, by cause";
    out.counter("nclink_bridge_drops_total", drop_help, {{"cause", "late_response"}}, s.late_responses);
    out.counter("nclink_bridge_drops_total", drop_help, {{"cause", "unmatched_response"}}, s.unmatched_responses);
    out.counter("nclink_bridge_drops_total", drop_help, {{"cause", "malformed"}}, s.malformed);
    out.counter("nclink_bridge_drops_total", drop_help, {{"cause", "outbox_full"}}, client_.transport().stats().dropped);
    out.counter("nclink_bridge_request_timeouts_total", "NC-Link requests without an answer in time", {}, s.timeouts);
    out.counter("nclink_bridge_unreachable_total", "NC-Link requests answered DEV_UNREACHABLE (8.3.4)", {}, s.unreachable);
    const auto t = client_.transport().stats();
    out.counter("nclink_bridge_mqtt_connects_total", "Successful (re)connections to the broker", {}, t.connects);
    out.gauge("nclink_bridge_mqtt_buffered_messages", "Messages waiting to go to the broker", {}, static_cast<double>(t.buffered));
    out.counter("nclink_bridge_mqtt_failovers_total",
                "Connections made to another broker of the failover list than the connection before", {}, t.failovers);
    if (!t.broker.empty())
        out.gauge("nclink_bridge_mqtt_broker", "1 for the broker connected to, or tried next while the link is down",
                  {{"broker", t.broker}}, 1);
    http_metrics_.render(out, "nclink_bridge");
    http::HttpMetrics::render(out, "nclink_bridge", server_.connection_counters());
    return out.str();
}

void OpsApi::install(http::HttpServer& server) {
    server.get("/metrics", [this](const http::HttpRequest&) {
        return http::text_response(metrics(), std::string(core_detail::prometheus_content_type));
    });
    server.get("/nclink/v1/health", [this](const http::HttpRequest&) { return http::json_response(health()); });
    // (the router treats /dashboard and /dashboard/ alike)
    server.get("/dashboard", [](const http::HttpRequest&) {
        auto r = http::text_response(std::string(kDashboardPage), "text/html; charset=utf-8");
        // The page only talks to this server: nothing else may run in it.
        r.headers.emplace_back(
            "Content-Security-Policy",
            "default-src 'self'; script-src 'self' 'unsafe-inline'; style-src 'unsafe-inline'; img-src 'self' data:; "
            "frame-ancestors 'none'");
        r.headers.emplace_back("X-Content-Type-Options", "nosniff");
        return r;
    });
}

}  // namespace nclink::bridge
