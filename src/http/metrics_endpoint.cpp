#include "http/metrics_endpoint.hpp"

#include "core/prometheus_text.hpp"

namespace nclink::http {

Result<std::pair<std::string, int>> parse_listen_address(const std::string& text) {
    const auto colon = text.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == text.size() || colon + 6 < text.size())
        return make_error(ErrorCode::value_type, "wants HOST:PORT, not '" + text + "'");
    std::string host = text.substr(0, colon);
    if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    int port = 0;
    for (char c : text.substr(colon + 1)) {
        if (c < '0' || c > '9') return make_error(ErrorCode::value_type, "wants HOST:PORT, not '" + text + "'");
        port = port * 10 + (c - '0');
    }
    if (port > 65535) return make_error(ErrorCode::out_of_range, "port " + std::to_string(port) + " is above 65535");
    return std::make_pair(host, port);
}

Result<std::unique_ptr<MetricsEndpoint>> MetricsEndpoint::start(const std::string& listen, std::function<std::string()> text,
                                                                const std::string& prefix, std::optional<BasicAuth> auth,
                                                                Logger logger, EndpointLimits limits) {
    auto address = parse_listen_address(listen);
    if (!address) return std::move(address).error();
    std::unique_ptr<MetricsEndpoint> endpoint(new MetricsEndpoint());
    HttpOptions options;
    options.host = address->first;
    options.port = address->second;
    options.workers = limits.workers;  // HttpServer takes 0 as 1
    options.header_timeout = limits.header_timeout;
    options.keep_alive_timeout = limits.keep_alive;
    options.write_timeout = limits.write_timeout;
    options.max_connections = limits.max_connections;
    options.max_connections_per_peer = limits.max_connections_per_peer;
    options.max_streams = 1;
    options.max_body_bytes = 1024;  // GET only: no body is wanted
    options.auth = std::move(auth);
    options.logger = std::move(logger);
    endpoint->host_ = options.host;
    endpoint->server_ = std::make_unique<HttpServer>(options);
    HttpMetrics& metrics = endpoint->metrics_;
    HttpServer& server = *endpoint->server_;
    endpoint->server_->set_observer(metrics.observer());
    endpoint->server_->get("/metrics", [text = std::move(text), &metrics, &server, prefix](const HttpRequest&) {
        core_detail::PrometheusText own;
        metrics.render(own, prefix);
        HttpMetrics::render(own, prefix, server.connection_counters());
        return text_response(text() + own.str(), std::string(core_detail::prometheus_content_type));
    });
    if (auto started = endpoint->server_->start(); !started) return std::move(started).error();
    return Result<std::unique_ptr<MetricsEndpoint>>(std::move(endpoint));
}

MetricsEndpoint::~MetricsEndpoint() {
    if (server_) server_->stop();
}

}  // namespace nclink::http
