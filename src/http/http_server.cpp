// HttpServer over cpp-httplib. httplib does the HTTP (parsing, keep-alive,
// chunked transfer, the 413 body cap); this file routes, fills in the
// answers nobody writes (404/405/413/503/500) and runs stream bodies.
#include "http/http_server.hpp"

#include "http/router.hpp"

#include <httplib.h>

#include <sys/socket.h>

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

struct HttpServer::Impl {
    explicit Impl(HttpOptions o) : options(std::move(o)) {
        if (options.workers == 0) options.workers = 1;
        if (options.max_streams == 0) options.max_streams = options.workers > 2 ? options.workers - 2 : 1;
    }

    HttpOptions options;
    Router router;
    std::vector<Handler> handlers;  // by route index
    ErrorPage error_page;
    httplib::Server server;
    std::thread listener;
    std::atomic<int> bound_port{0};
    std::atomic<bool> started{false};
    std::atomic<bool> stopped{false};
    std::atomic<std::size_t> streams{0};
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

    static HttpRequest convert(const httplib::Request& req) {
        HttpRequest r;
        r.method = req.method;
        r.path = req.path;
        r.query.insert(req.params.begin(), req.params.end());
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

    void dispatch(const httplib::Request& req, httplib::Response& res) {
        HttpRequest request = convert(req);
        const auto match = router.match(request.method, request.path);
        if (match.kind == Router::Match::Kind::no_path) {
            apply(error_response(404, request, "no resource " + request.path), res);
            return;
        }
        if (match.kind == Router::Match::Kind::no_method) {
            std::string allow;
            for (const auto& m : match.allowed) allow += (allow.empty() ? "" : ", ") + m;
            auto response = error_response(405, request, request.method + " is not served at " + request.path +
                                                             " (allowed: " + allow + ")");
            response.headers.emplace_back("Allow", allow);
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
                response = error_response(503, request, "too many streams at once (" +
                                                            std::to_string(options.max_streams) + ")");
            }
        }
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

int HttpServer::port() const noexcept { return impl_->bound_port; }

Result<void> HttpServer::start() {
    Impl& impl = *impl_;
    if (impl.stopped) return make_error(ErrorCode::unavailable, "http: start() after stop()");
    if (impl.started.exchange(true)) return make_error(ErrorCode::arguments_nimiety, "http: start() called twice");
    auto& svr = impl.server;
    const std::size_t workers = impl.options.workers;
    svr.new_task_queue = [workers] { return new httplib::ThreadPool(workers); };
    svr.set_payload_max_length(impl.options.max_body_bytes);
    svr.set_read_timeout(static_cast<time_t>(impl.options.read_timeout.count()), 0);
    svr.set_keep_alive_timeout(static_cast<time_t>(impl.options.keep_alive_timeout.count()));
    svr.set_tcp_nodelay(true);
    // httplib's default is SO_REUSEPORT, with which a second server silently
    // shares a port already in use; SO_REUSEADDR alone lets a restart rebind
    // at once yet makes a taken port an error.
    svr.set_socket_options([](int sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
    auto handler = [&impl](const httplib::Request& req, httplib::Response& res) { impl.dispatch(req, res); };
    svr.Get(".*", handler);
    svr.Post(".*", handler);
    svr.Put(".*", handler);
    svr.Patch(".*", handler);
    svr.Delete(".*", handler);
    svr.Options(".*", handler);
    // Answers httplib makes itself (413 body too large, 414, 400 for an
    // unknown method or a malformed request): give them our body.
    svr.set_error_handler(httplib::Server::HandlerWithResponse([&impl](const httplib::Request& req,
                                                                       httplib::Response& res) {
        if (!res.body.empty() || res.content_provider_) return httplib::Server::HandlerResponse::Unhandled;
        std::string reason = res.status == 413   ? "request body larger than " +
                                                       std::to_string(impl.options.max_body_bytes) + " bytes"
                             : res.status == 414 ? "request URI too long"
                                                 : "malformed request";
        auto response = impl.error_response(res.status, Impl::convert(req), reason);
        response.status = res.status;
        impl.apply(std::move(response), res);
        return httplib::Server::HandlerResponse::Handled;
    }));

    int port = impl.options.port;
    if (port == 0) {
        port = svr.bind_to_any_port(impl.options.host);
        if (port <= 0)
            return make_error(ErrorCode::unavailable, "http: cannot bind " + impl.options.host + " (any port)");
    } else if (!svr.bind_to_port(impl.options.host, port)) {
        return make_error(ErrorCode::unavailable,
                          "http: cannot bind " + impl.options.host + ":" + std::to_string(port));
    }
    impl.bound_port = port;
    impl.listener = std::thread([&impl] { impl.server.listen_after_bind(); });
    // stop() only reaches a server that is already listening: wait for it.
    for (int i = 0; i < 5000 && !svr.is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
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
    impl.server.stop();
    if (impl.listener.joinable()) impl.listener.join();
}

}  // namespace nclink::http
