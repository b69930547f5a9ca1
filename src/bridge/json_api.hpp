// The live JSON API for the OPC UA server and dashboards (docs/bridge.md
// "JSON API"): /nclink/v1/devices, .../{dev}/model, .../{dev}/nodeset.xml,
// .../{dev}/activity (method runs and events), the Server-Sent Events stream
// /nclink/v1/stream, .../{dev}/history (an item's buffered values), .../{dev}/set
// and .../{dev}/call (NC-Link Method/Call).
// Handlers run on HTTP worker threads; set blocks its worker for at most the
// request timeout, call for at most its timeout_ms.
#pragma once

#include "bridge/bridge_store.hpp"
#include "bridge/follower.hpp"
#include "http/http_server.hpp"

#include <chrono>

namespace nclink::bridge {

class JsonApi {
public:
    JsonApi(const BridgeStore& store, Follower& follower, std::chrono::milliseconds heartbeat)
        : store_(store), follower_(follower), heartbeat_(heartbeat) {}
    void install(http::HttpServer& server);

    /// One value of the stream and the snapshot: {"id","value","time","quality"}.
    static Json value_json(const ItemEntry& item, const Observation& o, const std::string& state);
    /// A method run of the stream (`event: method`) and of the activity:
    /// {"dev","ex","call","method","status","progress","result","code",
    /// "error","reason","return","start","time"} (absent parts left out).
    static Json method_run_json(const std::string& dev, const MethodRunEntry& run);
    /// An event of the stream (`event: event`): {"dev","ex","event","item","value","time"}.
    static Json event_json(const std::string& dev, const EventLogEntry& event);

private:
    http::HttpResponse devices() const;
    http::HttpResponse model(const std::string& dev) const;
    http::HttpResponse activity(const std::string& dev) const;
    http::HttpResponse nodeset(const std::string& dev, const std::string& profile) const;
    http::HttpResponse stream(const std::string& dev) const;
    http::HttpResponse set(const std::string& dev, const std::string& body) const;
    http::HttpResponse call(const std::string& dev, const std::string& body) const;
    http::HttpResponse history(const std::string& dev, const http::HttpRequest& request) const;

    const BridgeStore& store_;
    Follower& follower_;
    std::chrono::milliseconds heartbeat_;
};

}  // namespace nclink::bridge
