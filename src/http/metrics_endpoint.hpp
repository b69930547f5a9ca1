// A program's /metrics in one piece (docs/metrics.md): a small HttpServer
// that answers GET /metrics with the program's Prometheus text plus its own
// request metrics, and refuses everything else (404/405; bodies over 1 KiB
// get 413). Used by nclink-agent --metrics and nclink-sim --metrics.
//
// Thread-safety: `text` runs on the server's worker threads and must be
// thread-safe; start() and stop() from the owner's thread.
#pragma once

#include "http/http_metrics.hpp"
#include "http/http_server.hpp"

#include <nclink/http_limits.hpp>
#include <nclink/result.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace nclink::http {

/// "HOST:PORT" or "[V6]:PORT" -> host, port (0..65535).
Result<std::pair<std::string, int>> parse_listen_address(const std::string& text);

/// The HTTP limits of a metrics endpoint: the "metrics" section of the
/// agent's and the adapter's configuration (include/nclink/http_limits.hpp).
using EndpointLimits = HttpLimits;

class MetricsEndpoint {
public:
    /// Binds `listen` ("HOST:PORT"; loopback unless `auth` is given, as
    /// HttpServer requires) and serves `<prefix>_http_*` besides `text()`:
    /// the endpoint's own requests and its connection counters
    /// (HttpMetrics::render).
    static Result<std::unique_ptr<MetricsEndpoint>> start(const std::string& listen, std::function<std::string()> text,
                                                          const std::string& prefix, std::optional<BasicAuth> auth, Logger logger,
                                                          EndpointLimits limits = {});
    ~MetricsEndpoint();
    int port() const noexcept { return server_->port(); }
    const std::string& host() const noexcept { return host_; }
    void stop() { server_->stop(); }

private:
    MetricsEndpoint() = default;
    HttpMetrics metrics_;
    std::unique_ptr<HttpServer> server_;
    std::string host_;
};

}  // namespace nclink::http
