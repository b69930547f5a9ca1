// What an operator looks at (docs/dashboard.md, docs/metrics.md): the
// dashboard page at /dashboard/, the bridge's health at /nclink/v1/health
// (JSON, for the page) and its metrics at /metrics (Prometheus text).
// Handlers run on HTTP worker threads and only read thread-safe state.
#pragma once

#include "bridge/bridge_store.hpp"
#include "http/http_metrics.hpp"
#include "http/http_server.hpp"

#include <nclink/client.hpp>

#include <chrono>

namespace nclink::bridge {

class OpsApi {
public:
    OpsApi(const BridgeStore& store, const Client& client, const http::HttpServer& server, const http::HttpMetrics& http_metrics)
        : store_(store), client_(client), server_(server), http_metrics_(http_metrics) {}
    void install(http::HttpServer& server);

    Json health() const;
    std::string metrics() const;

private:
    const BridgeStore& store_;
    const Client& client_;
    const http::HttpServer& server_;
    const http::HttpMetrics& http_metrics_;
    const std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace nclink::bridge
