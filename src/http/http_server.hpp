// The one embedded HTTP server of nclink: a thin wrapper over cpp-httplib
// (Debian's libcpp-httplib-dev) for the programs that serve HTTP — the bridge
// (docs/bridge.md), and later the agent's dashboard and a Prometheus
// /metrics. nclink never parses HTTP itself; this file only adds what every
// such program needs on top of the library:
//
//  - bind host:port (default loopback; port 0 = any free port);
//  - routes per method with path parameters ("/devices/{dev}/model"); the
//    route with the most literal segments wins when several match;
//  - answers nobody has to write: 404 for an unknown path, 405 with an
//    `Allow` header for a known path and a method it does not serve, 413 for
//    a request body over the cap (the library's own check), 503 when every
//    stream slot is taken. Their body comes from ErrorPage (default: a small
//    JSON object), so an MTConnect program answers with its own documents;
//  - JSON responses (json_response);
//  - streaming responses (chunked transfer) with StreamSink, and Server-Sent
//    Events on top of it (SseWriter), both ended cleanly by stop();
//  - a bounded pool of worker threads and a clean, idempotent stop();
//  - slow and idle clients cost no worker (docs/bridge.md "Slow and idle
//    clients"): a connection reaches a worker only once its whole request
//    head has arrived (http/connection_gate.hpp); idle keep-alive
//    connections wait in the same poll set; heads that do not arrive within
//    header_timeout are closed; connections are capped in all and per peer;
//  - security for servers that reach beyond the machine (docs/dashboard.md
//    "Security"): loopback unless configured; bound anywhere else, start()
//    refuses to run without HTTP Basic authentication (RFC 7617), and then
//    every request without the credentials gets 401 (except those the
//    program exempts); a write (POST, PUT, PATCH, DELETE) whose Origin
//    header names another site gets 403, so a page on another site cannot
//    drive the server through the user's browser;
//  - an observer of every answered request (route, status, time), for
//    metrics (http/http_metrics.hpp).
//
// Threading contract:
//  - A handler runs on one of the server's worker threads (HttpOptions::
//    workers of them, created by start(), joined by stop()); handlers run
//    concurrently with each other, so whatever they share must be
//    thread-safe. A handler never runs on the caller of start()/stop().
//  - A stream body (HttpResponse::stream) runs on the thread of its request
//    for as long as the stream lasts; that thread stops counting as a worker
//    when the stream begins and a new worker takes its place, so streams
//    never hold request workers. At most HttpOptions::max_streams streams
//    run at once (the rest get 503).
//  - One more thread (the connection gate) accepts connections and holds the
//    waiting ones; it runs no handler.
//  - start(), stop(), port() and active_streams() may be called from any
//    thread; stop() must not be called from a handler (it joins the workers).
//  - The observer runs on the worker thread of the request, after its
//    handler (for a stream: when the stream begins); it must be thread-safe
//    and quick.
#pragma once

#include "http/connection_counters.hpp"

#include <nclink/json.hpp>
#include <nclink/log.hpp>
#include <nclink/result.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nclink::http {

struct HttpRequest;

/// HTTP Basic authentication (RFC 7617) of every request the server answers.
struct BasicAuth {
    std::string username;
    std::string password;
    std::string realm = "nclink";
    /// Requests that pass without credentials (e.g. anonymous reads of a
    /// public document); empty = none. Sees method, path and headers only.
    std::function<bool(const HttpRequest&)> exempt;
};

struct HttpOptions {
    std::string host = "127.0.0.1";  ///< loopback unless told otherwise
    int port = 0;                    ///< 0: any free port (see HttpServer::port())
    /// Worker threads serving requests (each one request at a time). Streams
    /// do not take them: a worker that begins a stream is replaced at once.
    std::size_t workers = 8;
    /// Streams (StreamSink) running at once, each on its own thread; more are answered 503. 0 = 32.
    std::size_t max_streams = 0;
    std::size_t max_body_bytes = 64 * 1024;  ///< request bodies over this get 413
    /// A connection's request head (request line and header fields) must be
    /// whole within this after the connection is accepted, or after the first
    /// byte of a later request on it; otherwise it is closed (408). Until its
    /// head is whole a connection takes no worker.
    std::chrono::milliseconds header_timeout{3000};
    /// A request's body must arrive within this after its head.
    std::chrono::milliseconds read_timeout{5000};
    /// A response must be taken by the client within this (a stream: each write).
    std::chrono::milliseconds write_timeout{5000};
    /// An idle keep-alive connection is closed after this; it waits without a worker.
    std::chrono::milliseconds keep_alive_timeout{5000};
    std::size_t keep_alive_max_requests = 100;  ///< requests on one connection before it is closed
    /// Connections open at once (all peers); more are closed at once.
    std::size_t max_connections = 512;
    /// Connections open at once from one address; more are closed at once. 0 = no cap.
    std::size_t max_connections_per_peer = 64;
    /// Required when `host` is not a loopback address (start() fails without).
    std::optional<BasicAuth> auth;
    /// 403 for a POST/PUT/PATCH/DELETE whose Origin is not this server's Host.
    bool same_origin_writes = true;
    Logger logger;
};

/// True for addresses only this machine reaches: 127.0.0.0/8, ::1, localhost.
bool is_loopback_host(std::string_view host);

/// The credentials of an `Authorization: Basic ...` header value, if it is one.
std::optional<std::pair<std::string, std::string>> parse_basic_authorization(std::string_view header);

struct HttpRequest {
    std::string method;                               ///< "GET", "POST", ... (HEAD is served by the GET route)
    std::string path;                                 ///< decoded path, no query
    std::map<std::string, std::string> path_params;   ///< "{dev}" -> value
    std::multimap<std::string, std::string> query;    ///< decoded query parameters
    std::multimap<std::string, std::string> headers;  ///< names as sent (look up with header())
    std::string body;
    std::string remote_addr;

    /// The first value of a query parameter.
    std::optional<std::string> param(const std::string& name) const;
    /// A header, names compared without case.
    std::optional<std::string> header(std::string_view name) const;
    /// A path parameter ("" when the route has none of that name).
    const std::string& path_param(const std::string& name) const;
};

/// Where a stream body writes. Owned by the server; valid only during the body call.
class StreamSink {
public:
    virtual ~StreamSink() = default;
    /// Sends `data` as one chunk at once. False when the client went away or
    /// the server is stopping: the body should return then.
    virtual bool write(std::string_view data) = 0;
    /// True once stop() began: the body should return promptly.
    virtual bool stopping() const = 0;
    /// Sleeps up to `timeout`, returning early (false) when the server stops.
    virtual bool sleep_for(std::chrono::milliseconds timeout) = 0;
};

/// The body of a streaming response; runs on the request's worker thread
/// until it returns (then the response ends cleanly with the last chunk).
using StreamBody = std::function<void(StreamSink&)>;

struct HttpResponse {
    int status = 200;
    std::string content_type = "text/plain; charset=utf-8";
    std::string body;
    std::vector<std::pair<std::string, std::string>> headers;
    /// When set, the response is streamed (chunked) from this body instead of `body`.
    StreamBody stream;
};

using Handler = std::function<HttpResponse(const HttpRequest&)>;

/// One answered request, as the observer sees it.
struct RequestRecord {
    std::string_view method;
    std::string_view route;  ///< the route's pattern ("/devices/{dev}/model"); "" when no route matched
    int status = 0;
    std::chrono::nanoseconds elapsed{0};  ///< from dispatch to the answer (a stream: to its start)
    bool stream = false;
};
using RequestObserver = std::function<void(const RequestRecord&)>;

/// The body of the answers the server makes itself (404, 405, 413, 503, 500
/// and 400 for malformed requests): status, the request as far as it was read,
/// and a one-line reason. The status of the returned response is ignored.
using ErrorPage = std::function<HttpResponse(int status, const HttpRequest&, const std::string& reason)>;

/// A JSON response (application/json, UTF-8, invalid UTF-8 replaced).
HttpResponse json_response(const Json& body, int status = 200);
/// A plain response of the given type.
HttpResponse text_response(std::string body, std::string content_type, int status = 200);

/// Server-Sent Events on a StreamSink (text/event-stream framing: "event:",
/// "data:" per line, blank line; comments start with ':').
class SseWriter {
public:
    explicit SseWriter(StreamSink& sink) : sink_(sink) {}
    /// One event; `data` may hold several lines. False when the stream ended.
    bool event(std::string_view name, std::string_view data);
    /// A comment line (": text"), e.g. a heartbeat. False when the stream ended.
    bool comment(std::string_view text);

private:
    StreamSink& sink_;
};

/// The content type of a Server-Sent Events stream.
inline constexpr std::string_view sse_content_type = "text/event-stream";

class HttpServer {
public:
    explicit HttpServer(HttpOptions options);
    ~HttpServer();  ///< stop()s
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    /// Registers `handler` for `method` ("GET", "POST", "PUT", "DELETE",
    /// "PATCH") and `pattern`: "/" separated segments, a segment "{name}"
    /// matches any one non-empty segment and is passed as a path parameter.
    /// Before start() only (not thread-safe against serving).
    void route(std::string method, std::string pattern, Handler handler);
    void get(std::string pattern, Handler handler) { route("GET", std::move(pattern), std::move(handler)); }
    void post(std::string pattern, Handler handler) { route("POST", std::move(pattern), std::move(handler)); }
    /// Replaces the default JSON error bodies. Before start() only.
    void set_error_page(ErrorPage page);
    /// Called for every answered request (metrics). Before start() only.
    void set_observer(RequestObserver observer);

    /// Binds and starts serving on a background thread. Fails (unavailable)
    /// when the address cannot be bound. Once only.
    Result<void> start();
    /// The bound port (useful with port 0); 0 before start().
    int port() const noexcept;
    /// Streams running now.
    std::size_t active_streams() const noexcept;
    /// What the connection gate did so far (connections open, refused, timed out).
    ConnectionCounters connection_counters() const;
    /// Ends every stream, stops accepting, waits for the workers. Idempotent.
    void stop();

    struct Impl;

private:
    std::shared_ptr<Impl> impl_;
};

}  // namespace nclink::http
