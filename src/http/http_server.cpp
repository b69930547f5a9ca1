// HttpServer over cpp-httplib. httplib does the HTTP (parsing, chunked
// transfer, the 413 body cap) one request at a time on a connection the gate
// (http/connection_gate.hpp) hands over with its head complete; this file
// routes, fills in the answers nobody writes (404/405/413/503/500), runs
// stream bodies and moves connections between the gate and the workers.
#include "http/http_server.hpp"

#include "http/connection_gate.hpp"
#include "http/router.hpp"
#include "http/worker_pool.hpp"

#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace nclink::http {

// ------------------------------------------------------------------ request helpers

std::optional<std::string> HttpRequest::param(const std::string& name) const {
    auto it = query.find(name);
    if (it == query.end()) return std::nullopt;
    return it->second;
}

std::optional<std::string> HttpRequest::header(std::string_view name) const {
    for (const auto& [key, value] : headers) {
        if (key.size() != name.size()) continue;
        bool same = true;
        for (std::size_t i = 0; i < key.size() && same; ++i)
            same = std::tolower(static_cast<unsigned char>(key[i])) == std::tolower(static_cast<unsigned char>(name[i]));
        if (same) return value;
    }
    return std::nullopt;
}

const std::string& HttpRequest::path_param(const std::string& name) const {
    static const std::string empty;
    auto it = path_params.find(name);
    return it == path_params.end() ? empty : it->second;
}

HttpResponse json_response(const Json& body, int status) {
    HttpResponse r;
    r.status = status;
    r.content_type = "application/json";
    r.body = body.dump(-1, ' ', false, Json::error_handler_t::replace);
    return r;
}

HttpResponse text_response(std::string body, std::string content_type, int status) {
    HttpResponse r;
    r.status = status;
    r.content_type = std::move(content_type);
    r.body = std::move(body);
    return r;
}

// ------------------------------------------------------------------ security

bool is_loopback_host(std::string_view host) {
    if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    if (host == "localhost" || host == "::1" || host == "0:0:0:0:0:0:0:1") return true;
    // 127.0.0.0/8, written as four decimal parts
    if (host.rfind("127.", 0) != 0) return false;
    int parts = 0, digits = 0, value = 0;
    for (char c : host) {
        if (c == '.') {
            if (digits == 0) return false;
            ++parts, digits = 0, value = 0;
        } else if (c >= '0' && c <= '9') {
            value = value * 10 + (c - '0');
            if (++digits > 3 || value > 255) return false;
        } else {
            return false;
        }
    }
    return parts == 3 && digits > 0;
}

namespace {

int base64_value(char c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

std::optional<std::string> base64_decode(std::string_view text) {
    while (!text.empty() && text.back() == '=') text.remove_suffix(1);
    std::string out;
    unsigned buffer = 0;
    int bits = 0;
    for (char c : text) {
        const int v = base64_value(c);
        if (v < 0) return std::nullopt;
        buffer = (buffer << 6) | static_cast<unsigned>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out += static_cast<char>((buffer >> bits) & 0xFF);
        }
    }
    if (bits >= 6) return std::nullopt;  // a lone sixth of a byte: not base64
    return out;
}

// Compares without stopping at the first difference, so the time taken does
// not tell an attacker how much of a guess was right.
bool same_secret(std::string_view given, std::string_view expected) {
    std::size_t diff = given.size() ^ expected.size();
    for (std::size_t i = 0; i < given.size(); ++i)
        diff |= static_cast<unsigned char>(given[i]) ^
                (expected.empty() ? 0u : static_cast<unsigned char>(expected[i % expected.size()]));
    return diff == 0;
}

bool is_write(std::string_view method) { return method == "POST" || method == "PUT" || method == "PATCH" || method == "DELETE"; }

// "http://host:port" -> "host:port"; "" when it is no http(s) origin.
std::string_view origin_authority(std::string_view origin) {
    for (std::string_view scheme : {"http://", "https://"})
        if (origin.rfind(scheme, 0) == 0) return origin.substr(scheme.size());
    return {};
}

}  // namespace

std::optional<std::pair<std::string, std::string>> parse_basic_authorization(std::string_view header) {
    std::size_t i = 0;
    while (i < header.size() && header[i] == ' ') ++i;
    header.remove_prefix(i);
    if (header.size() < 6) return std::nullopt;
    for (std::size_t k = 0; k < 5; ++k)
        if (std::tolower(static_cast<unsigned char>(header[k])) != "basic"[k]) return std::nullopt;
    if (header[5] != ' ') return std::nullopt;
    header.remove_prefix(6);
    while (!header.empty() && header.front() == ' ') header.remove_prefix(1);
    while (!header.empty() && header.back() == ' ') header.remove_suffix(1);
    auto decoded = base64_decode(header);
    if (!decoded) return std::nullopt;
    const auto colon = decoded->find(':');
    if (colon == std::string::npos) return std::nullopt;
    return std::make_pair(decoded->substr(0, colon), decoded->substr(colon + 1));
}

// ------------------------------------------------------------------ SSE

namespace {
// "data:" once per line of `data` (a CR, LF or CRLF ends a line, 9.2.6 of
// the HTML event-stream format), so multi-line payloads survive.
void append_data_lines(std::string& out, std::string_view data) {
    std::size_t start = 0;
    for (std::size_t i = 0; i <= data.size(); ++i) {
        if (i == data.size() || data[i] == '\n' || data[i] == '\r') {
            out += "data: ";
            out.append(data.substr(start, i - start));
            out += '\n';
            if (i + 1 < data.size() && data[i] == '\r' && data[i + 1] == '\n') ++i;
            start = i + 1;
        }
    }
}

std::string one_line(std::string_view text) {
    std::string out(text);
    std::replace(out.begin(), out.end(), '\n', ' ');
    std::replace(out.begin(), out.end(), '\r', ' ');
    return out;
}
}  // namespace

bool SseWriter::event(std::string_view name, std::string_view data) {
    std::string frame;
    frame.reserve(name.size() + data.size() + 24);
    if (!name.empty()) {
        frame += "event: ";
        frame += one_line(name);
        frame += '\n';
    }
    append_data_lines(frame, data);
    frame += '\n';
    return sink_.write(frame);
}

bool SseWriter::comment(std::string_view text) {
    std::string frame = ": " + one_line(text) + "\n\n";
    return sink_.write(frame);
}

// ------------------------------------------------------------------ server

namespace {

// cpp-httplib's request processing for one request on a stream we own. The
// library's own accept loop and keep-alive wait (which hold a worker per
// connection, idle or not) are not used; process_request() is the library's
// protected entry for one request. Its "shutting down" test is that the
// listening socket it knows is invalid: serving(true) marks it valid (the
// value is never used as a socket, as listen() and stop() are never called).
class Engine final : public httplib::Server {
public:
    bool serve_one(httplib::Stream& stream, bool last, bool& closed) { return process_request(stream, last, closed, nullptr); }
    void serving(bool on) { svr_sock_ = on ? 0 : INVALID_SOCKET; }
};

// The stream of the request this worker thread serves now (dispatch marks it
// streaming when the response is a stream).
thread_local ConnectionStream* current_stream = nullptr;

GateOptions gate_options(const HttpOptions& o) {
    GateOptions g;
    g.header_timeout = o.header_timeout;
    g.keep_alive_timeout = o.keep_alive_timeout;
    g.max_connections = o.max_connections;
    g.max_connections_per_peer = o.max_connections_per_peer;
    return g;
}

}  // namespace

struct HttpServer::Impl {
    explicit Impl(HttpOptions o) : options(std::move(o)), gate(gate_options(options), options.logger) {
        if (options.workers == 0) options.workers = 1;
        if (options.max_streams == 0) options.max_streams = 32;
        if (options.keep_alive_max_requests == 0) options.keep_alive_max_requests = 1;
    }

    HttpOptions options;
    Router router;
    std::vector<Handler> handlers;  // by route index
    ErrorPage error_page;
    RequestObserver observer;
    Engine server;
    ConnectionGate gate;
    std::unique_ptr<WorkerPool> pool;
    std::atomic<int> bound_port{0};
    std::atomic<bool> started{false};
    std::atomic<bool> stopped{false};
    std::atomic<std::size_t> streams{0};
    std::atomic<std::uint64_t> streams_started{0};
    std::atomic<std::uint64_t> streams_refused{0};
    std::mutex stop_mutex;
    std::condition_variable stop_cv;

    HttpResponse error_response(int status, const HttpRequest& request, const std::string& reason) const {
        HttpResponse r;
        if (error_page) {
            r = error_page(status, request, reason);
        } else {
            r = json_response(Json{{"error", reason}, {"status", status}});
        }
        r.status = status;
        return r;
    }

    // The query from the raw target, each pair split at its FIRST '=': a
    // browser leaves '=' inside a value unencoded (MTConnect's
    // path=//DataItem[@type="POSITION"]), and the library's own parse keeps
    // only what follows the last one.
    static std::multimap<std::string, std::string> query_of(const httplib::Request& req) {
        const auto mark = req.target.find('?');
        if (mark == std::string::npos) return {req.params.begin(), req.params.end()};
        std::multimap<std::string, std::string> out;
        const std::string raw = req.target.substr(mark + 1);
        std::size_t at = 0;
        while (at <= raw.size()) {
            const auto end = std::min(raw.find('&', at), raw.size());
            const std::string pair = raw.substr(at, end - at);
            if (!pair.empty()) {
                const auto eq = pair.find('=');
                out.emplace(httplib::detail::decode_url(pair.substr(0, eq), true),
                            eq == std::string::npos ? std::string() : httplib::detail::decode_url(pair.substr(eq + 1), true));
            }
            at = end + 1;
        }
        return out;
    }

    static HttpRequest convert(const httplib::Request& req) {
        HttpRequest r;
        r.method = req.method;
        r.path = req.path;
        r.query = query_of(req);
        r.headers.insert(req.headers.begin(), req.headers.end());
        r.body = req.body;
        r.remote_addr = req.remote_addr;
        return r;
    }

    void apply(HttpResponse response, httplib::Response& res) {
        res.status = response.status;
        for (const auto& [name, value] : response.headers) res.set_header(name, value);
        if (!response.stream) {
            res.set_content(std::move(response.body), response.content_type.c_str());
            return;
        }
        // The slot was taken by dispatch(); the releaser gives it back whether
        // or not the body ever ran (a HEAD request, a client gone early).
        auto body = std::make_shared<StreamBody>(std::move(response.stream));
        res.set_chunked_content_provider(
            response.content_type,
            [this, body](std::size_t, httplib::DataSink& sink) {
                SinkAdapter adapter(*this, sink);
                try {
                    (*body)(adapter);
                } catch (const std::exception& e) {
                    options.logger.warn("http: stream body threw: {}", e.what());
                } catch (...) {
                    options.logger.warn("http: stream body threw");
                }
                sink.done();
                return true;
            },
            [this](bool) { --streams; });
    }

    class SinkAdapter final : public StreamSink {
    public:
        SinkAdapter(Impl& impl, httplib::DataSink& sink) : impl_(impl), sink_(sink) {}
        bool write(std::string_view data) override {
            if (impl_.stopped || !ok_) return false;
            if (data.empty()) return true;
            ok_ = sink_.write(data.data(), data.size());
            return ok_;
        }
        bool stopping() const override { return impl_.stopped; }
        bool sleep_for(std::chrono::milliseconds timeout) override {
            std::unique_lock<std::mutex> lock(impl_.stop_mutex);
            return !impl_.stop_cv.wait_for(lock, timeout, [&] { return impl_.stopped.load(); });
        }

    private:
        Impl& impl_;
        httplib::DataSink& sink_;
        bool ok_ = true;
    };

    void observe(std::string_view method, std::string_view route, int status, std::chrono::steady_clock::time_point begun,
                 bool stream) const {
        if (!observer) return;
        try {
            observer(RequestRecord{method, route, status, std::chrono::steady_clock::now() - begun, stream});
        } catch (...) {
            // metrics never break an answer
        }
    }

    // 401 / 403 before anything else; nullopt lets the request through.
    std::optional<HttpResponse> refuse(const HttpRequest& request) const {
        if (options.auth) {
            const BasicAuth& auth = *options.auth;
            const bool exempt = auth.exempt && auth.exempt(request);
            std::optional<std::pair<std::string, std::string>> given;
            if (auto header = request.header("Authorization")) given = parse_basic_authorization(*header);
            const bool user_ok = given && same_secret(given->first, auth.username);
            const bool password_ok = given && same_secret(given->second, auth.password);
            if (!exempt && !(user_ok && password_ok)) {
                auto response = error_response(401, request, given ? "wrong credentials" : "authentication required");
                response.headers.emplace_back("WWW-Authenticate", "Basic realm=\"" + auth.realm + "\", charset=\"UTF-8\"");
                return response;
            }
        }
        if (options.same_origin_writes && is_write(request.method)) {
            if (auto origin = request.header("Origin")) {
                const auto host = request.header("Host").value_or("");
                if (origin_authority(*origin).empty() || origin_authority(*origin) != host)
                    return error_response(403, request, "a write from another site (Origin " + *origin + ") is refused");
            }
        }
        return std::nullopt;
    }

    // A worker's job: the requests of one connection whose head is buffered,
    // then the connection goes back to the gate (or is closed).
    void serve_connection(std::unique_ptr<Connection> c) {
        for (;;) {
            if (stopped) return gate.close(std::move(c));
            ConnectionStream stream(*c, Connection::Clock::now() + options.read_timeout, options.write_timeout);
            const bool last = ++c->requests >= options.keep_alive_max_requests;
            bool closed = false;
            current_stream = &stream;
            const bool ok = server.serve_one(stream, last, closed);
            current_stream = nullptr;
            if (!ok || closed || last || !stream.healthy() || stopped) return gate.close(std::move(c));
            c->compact();
            if (c->head_ready()) continue;  // the next request is already here
            c->idle = c->pending().empty();
            c->deadline = Connection::Clock::now() + (c->idle ? options.keep_alive_timeout : options.header_timeout);
            return gate.give_back(std::move(c));
        }
    }

    void dispatch(const httplib::Request& req, httplib::Response& res) {
        const auto begun = std::chrono::steady_clock::now();
        HttpRequest request = convert(req);
        if (auto refused = refuse(request)) {
            observe(request.method, "", refused->status, begun, false);
            apply(std::move(*refused), res);
            return;
        }
        const auto match = router.match(request.method, request.path);
        if (match.kind == Router::Match::Kind::no_path) {
            observe(request.method, "", 404, begun, false);
            apply(error_response(404, request, "no resource " + request.path), res);
            return;
        }
        if (match.kind == Router::Match::Kind::no_method) {
            std::string allow;
            for (const auto& m : match.allowed) allow += (allow.empty() ? "" : ", ") + m;
            auto response =
                error_response(405, request, request.method + " is not served at " + request.path + " (allowed: " + allow + ")");
            response.headers.emplace_back("Allow", allow);
            observe(request.method, "", 405, begun, false);
            apply(std::move(response), res);
            return;
        }
        request.path_params = match.params;
        HttpResponse response;
        try {
            response = handlers[match.route](request);
        } catch (const std::exception& e) {
            options.logger.warn("http: handler of {} threw: {}", request.path, e.what());
            response = error_response(500, request, "internal error");
        } catch (...) {
            response = error_response(500, request, "internal error");
        }
        if (response.stream) {
            if (stopped) {
                response = error_response(503, request, "the server is stopping");
            } else if (++streams > options.max_streams) {
                --streams;
                ++streams_refused;
                response = error_response(503, request, "too many streams at once (" + std::to_string(options.max_streams) + ")");
            } else {
                ++streams_started;
                // The stream keeps this thread; a new worker takes its place.
                if (current_stream) current_stream->streaming();
                if (pool) pool->lend_current();
            }
        }
        observe(request.method, router.pattern(match.route), response.status, begun, static_cast<bool>(response.stream));
        apply(std::move(response), res);
    }
};

HttpServer::HttpServer(HttpOptions options) : impl_(std::make_shared<Impl>(std::move(options))) {}

HttpServer::~HttpServer() { stop(); }

void HttpServer::route(std::string method, std::string pattern, Handler handler) {
    impl_->router.add(std::move(method), pattern);
    impl_->handlers.push_back(std::move(handler));
}

void HttpServer::set_error_page(ErrorPage page) { impl_->error_page = std::move(page); }

void HttpServer::set_observer(RequestObserver observer) { impl_->observer = std::move(observer); }

int HttpServer::port() const noexcept { return impl_->bound_port; }

std::size_t HttpServer::active_streams() const noexcept { return impl_->streams; }

Result<void> HttpServer::start() {
    Impl& impl = *impl_;
    if (impl.stopped) return make_error(ErrorCode::unavailable, "http: start() after stop()");
    if (impl.started.exchange(true)) return make_error(ErrorCode::arguments_nimiety, "http: start() called twice");
    if (!is_loopback_host(impl.options.host) &&
        (!impl.options.auth || impl.options.auth->username.empty() || impl.options.auth->password.empty()))
        return make_error(ErrorCode::permission_denied,
                          "http: " + impl.options.host +
                              " is not a loopback address: serving it needs a username and password "
                              "(HTTP Basic; docs/dashboard.md, Security)");
    auto& svr = impl.server;
    svr.set_payload_max_length(impl.options.max_body_bytes);
    // Only what the library writes in its Keep-Alive header; the gate keeps
    // the real time (in milliseconds) and the worker the real count.
    svr.set_keep_alive_timeout(static_cast<time_t>((impl.options.keep_alive_timeout.count() + 999) / 1000));
    svr.set_keep_alive_max_count(impl.options.keep_alive_max_requests);
    auto handler = [&impl](const httplib::Request& req, httplib::Response& res) { impl.dispatch(req, res); };
    svr.Get(".*", handler);
    svr.Post(".*", handler);
    svr.Put(".*", handler);
    svr.Patch(".*", handler);
    svr.Delete(".*", handler);
    svr.Options(".*", handler);
    // Answers httplib makes itself (413 body too large, 414, 400 for an
    // unknown method or a malformed request): give them our body.
    svr.set_error_handler(httplib::Server::HandlerWithResponse([&impl](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty() || res.content_provider_) return httplib::Server::HandlerResponse::Unhandled;
        std::string reason = res.status == 413
                                 ? "request body larger than " + std::to_string(impl.options.max_body_bytes) + " bytes"
                             : res.status == 414 ? "request URI too long"
                                                 : "malformed request";
        auto response = impl.error_response(res.status, Impl::convert(req), reason);
        response.status = res.status;
        impl.observe(req.method, "", res.status, std::chrono::steady_clock::now(), false);
        impl.apply(std::move(response), res);
        return httplib::Server::HandlerResponse::Handled;
    }));

    auto bound = impl.gate.bind(impl.options.host, impl.options.port);
    if (!bound) return std::move(bound).error();
    const int port = *bound;
    impl.bound_port = port;
    impl.server.serving(true);
    impl.pool = std::make_unique<WorkerPool>(impl.options.workers);
    impl.gate.start([&impl](std::unique_ptr<Connection> c) {
        auto shared = std::make_shared<std::unique_ptr<Connection>>(std::move(c));
        if (!impl.pool->submit([&impl, shared] { impl.serve_connection(std::move(*shared)); }))
            impl.gate.close(std::move(*shared));
    });
    impl.options.logger.info("http: serving on {}:{}", impl.options.host, port);
    return ok_result();
}

void HttpServer::stop() {
    Impl& impl = *impl_;
    {
        std::lock_guard<std::mutex> lock(impl.stop_mutex);
        if (impl.stopped.exchange(true)) return;
    }
    impl.stop_cv.notify_all();
    if (!impl.started) return;
    impl.server.serving(false);  // a running stream's chunk loop ends
    impl.gate.stop();            // no new connections; the waiting ones are closed
    // Streams end cleanly (their last chunk) once they see `stopped`; give
    // them a moment before every served connection's socket is shut down.
    for (int i = 0; i < 100 && impl.streams > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    impl.gate.interrupt_served();  // reads and writes of requests still served end
    if (impl.pool) impl.pool->shutdown();
}

ConnectionCounters HttpServer::connection_counters() const {
    ConnectionCounters c = impl_->gate.counters();
    c.streams_started = impl_->streams_started;
    c.streams_refused = impl_->streams_refused;
    c.streams = impl_->streams;
    return c;
}

}  // namespace nclink::http
