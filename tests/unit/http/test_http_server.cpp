// The HTTP server wrapper against a real HTTP client (cpp-httplib's) on loopback.
#include "http/http_server.hpp"
#include "http/router.hpp"

#include "support/wait.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <atomic>
#include <future>
#include <thread>

using namespace nclink;
using namespace nclink::http;
using namespace std::chrono_literals;

namespace {

HttpOptions small_options() {
    HttpOptions o;
    o.workers = 4;
    o.max_streams = 1;
    o.max_body_bytes = 1024;
    o.keep_alive_timeout = std::chrono::seconds(1);
    return o;
}

}  // namespace

TEST_CASE("router picks the route with the most literal segments") {
    Router router;
    const auto any_probe = router.add("GET", "/{device}/probe");
    const auto gbt_probe = router.add("GET", "/gbt18759/probe");
    router.add("POST", "/gbt18759/write");
    auto m = router.match("GET", "/gbt18759/probe");
    REQUIRE(m.kind == Router::Match::Kind::found);
    CHECK(m.route == gbt_probe);
    m = router.match("GET", "/mill/probe");
    REQUIRE(m.kind == Router::Match::Kind::found);
    CHECK(m.route == any_probe);
    CHECK(m.params.at("device") == "mill");
    m = router.match("HEAD", "/mill/probe");
    CHECK(m.kind == Router::Match::Kind::found);
    m = router.match("GET", "/gbt18759/write");
    REQUIRE(m.kind == Router::Match::Kind::no_method);
    CHECK(m.allowed == std::vector<std::string>{"POST"});
    CHECK(router.match("GET", "/a/b/c").kind == Router::Match::Kind::no_path);
    CHECK(split_path("//a//b/").size() == 2);
}

TEST_CASE("http server routes with path parameters and answers JSON") {
    HttpServer server(small_options());
    server.get("/devices/{dev}/model", [](const HttpRequest& r) {
        return json_response(Json{{"dev", r.path_param("dev")}, {"q", r.param("q").value_or("")}});
    });
    REQUIRE(server.start().ok());
    REQUIRE(server.port() > 0);
    httplib::Client client("127.0.0.1", server.port());
    auto res = client.Get("/devices/mill-1/model?q=a%20b");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(res->get_header_value("Content-Type") == "application/json");
    const auto body = Json::parse(res->body);
    CHECK(body["dev"] == "mill-1");
    CHECK(body["q"] == "a b");
    // An '=' inside a value, as a browser sends it (MTConnect path=): the
    // pair splits at its first '='.
    res = client.Get("/devices/mill-1/model?q=//DataItem%5B@type=%22POSITION%22%5D&x=1");
    REQUIRE(res);
    CHECK(Json::parse(res->body)["q"] == "//DataItem[@type=\"POSITION\"]");
    server.stop();
}

TEST_CASE("http server answers 404 for unknown paths and 405 with Allow for other methods") {
    HttpServer server(small_options());
    server.get("/only-get", [](const HttpRequest&) { return text_response("ok", "text/plain"); });
    REQUIRE(server.start().ok());
    httplib::Client client("127.0.0.1", server.port());
    auto res = client.Get("/nothing/here");
    REQUIRE(res);
    CHECK(res->status == 404);
    CHECK(Json::parse(res->body)["status"] == 404);
    res = client.Post("/only-get", "x", "text/plain");
    REQUIRE(res);
    CHECK(res->status == 405);
    CHECK(res->get_header_value("Allow") == "GET, HEAD");
    res = client.Get("/only-get");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(res->body == "ok");
}

TEST_CASE("http server refuses bodies over the cap with 413 and its error page") {
    HttpServer server(small_options());
    std::atomic<int> calls{0};
    server.post("/upload", [&](const HttpRequest&) {
        ++calls;
        return text_response("taken", "text/plain");
    });
    server.set_error_page([](int status, const HttpRequest&, const std::string& reason) {
        return text_response("<Error code=\"" + std::to_string(status) + "\">" + reason + "</Error>", "application/xml");
    });
    REQUIRE(server.start().ok());
    httplib::Client client("127.0.0.1", server.port());
    auto res = client.Post("/upload", std::string(4096, 'x'), "text/plain");
    REQUIRE(res);
    CHECK(res->status == 413);
    CHECK(res->body.find("<Error code=\"413\">") == 0);
    CHECK(calls == 0);
    httplib::Client again("127.0.0.1", server.port());
    res = again.Post("/upload", std::string(100, 'x'), "text/plain");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(calls == 1);
}

TEST_CASE("http server turns a throwing handler into 500 and keeps serving") {
    HttpServer server(small_options());
    server.get("/boom", [](const HttpRequest&) -> HttpResponse { throw std::runtime_error("boom"); });
    server.get("/fine", [](const HttpRequest&) { return text_response("fine", "text/plain"); });
    REQUIRE(server.start().ok());
    httplib::Client client("127.0.0.1", server.port());
    auto res = client.Get("/boom");
    REQUIRE(res);
    CHECK(res->status == 500);
    res = client.Get("/fine");
    REQUIRE(res);
    CHECK(res->status == 200);
}

TEST_CASE("server-sent events stream until stop and end cleanly") {
    HttpServer server(small_options());
    server.get("/events", [](const HttpRequest&) {
        HttpResponse r;
        r.content_type = std::string(sse_content_type);
        r.stream = [](StreamSink& sink) {
            SseWriter sse(sink);
            if (!sse.event("snapshot", "{\"a\":1}\n{\"b\":2}")) return;
            while (sink.sleep_for(20ms))
                if (!sse.comment("ping")) return;
        };
        return r;
    });
    server.get("/plain", [](const HttpRequest&) { return text_response("plain", "text/plain"); });
    REQUIRE(server.start().ok());

    std::promise<void> first_event;
    std::atomic<bool> signalled{false};
    std::string received;
    std::mutex received_mutex;
    auto reader = std::async(std::launch::async, [&] {
        httplib::Client client("127.0.0.1", server.port());
        client.set_read_timeout(10, 0);
        return client.Get("/events", [&](const char* data, size_t length) {
            std::lock_guard<std::mutex> lock(received_mutex);
            received.append(data, length);
            if (received.find("ping") != std::string::npos && !signalled.exchange(true)) first_event.set_value();
            return true;
        });
    });
    REQUIRE(first_event.get_future().wait_for(10s) == std::future_status::ready);

    // The one stream slot is taken: a second stream is refused, plain requests still work.
    httplib::Client other("127.0.0.1", server.port());
    auto refused = other.Get("/events");
    REQUIRE(refused);
    CHECK(refused->status == 503);
    auto plain = other.Get("/plain");
    REQUIRE(plain);
    CHECK(plain->status == 200);

    server.stop();
    REQUIRE(reader.wait_for(10s) == std::future_status::ready);
    auto res = reader.get();
    REQUIRE(res);  // the chunked response ended with its last chunk, not an error
    CHECK(res->status == 200);
    CHECK(res->get_header_value("Content-Type") == "text/event-stream");
    std::lock_guard<std::mutex> lock(received_mutex);
    CHECK(received.find("event: snapshot\ndata: {\"a\":1}\ndata: {\"b\":2}\n\n") == 0);
    CHECK(received.find(": ping\n\n") != std::string::npos);
}

TEST_CASE("http server reports a port it cannot bind") {
    HttpServer first(small_options());
    REQUIRE(first.start().ok());
    auto options = small_options();
    options.port = first.port();
    HttpServer second(options);
    auto started = second.start();
    REQUIRE_FALSE(started.ok());
    CHECK(started.error().code == ErrorCode::unavailable);
    second.stop();
    first.stop();
    first.stop();  // idempotent
}
