// What the servers that reach beyond the machine need (the dashboard, /metrics):
// loopback unless configured, HTTP Basic authentication otherwise, writes
// only from the same origin, and the request metrics of the observer.
#include "http/http_metrics.hpp"
#include "http/http_server.hpp"
#include "http/metrics_endpoint.hpp"

#include "support/prometheus_check.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

using namespace nclink;
using namespace nclink::http;

namespace {

HttpOptions small_options() {
    HttpOptions o;
    o.workers = 3;
    o.max_streams = 1;
    o.max_body_bytes = 1024;
    o.keep_alive_timeout = std::chrono::seconds(1);
    return o;
}

}  // namespace

TEST_CASE("http security: loopback names are told from every other address") {
    for (const char* host : {"127.0.0.1", "127.1.2.3", "localhost", "::1", "[::1]"}) CHECK(is_loopback_host(host));
    for (const char* host : {"0.0.0.0", "::", "192.168.1.10", "127.0.0.1.example.com", "127.0.0.256", "1127.0.0.1", ""})
        CHECK_FALSE(is_loopback_host(host));
}

TEST_CASE("http security: a server bound beyond loopback refuses to start without credentials") {
    HttpOptions o = small_options();
    o.host = "0.0.0.0";
    HttpServer open(o);
    const auto started = open.start();
    REQUIRE_FALSE(started.ok());
    CHECK(started.error().code == ErrorCode::permission_denied);
    CHECK_THAT(started.error().message, Catch::Contains("loopback"));

    o.auth = BasicAuth{"ops", "s3cret", "test", {}};
    HttpServer guarded(o);
    guarded.get("/x", [](const HttpRequest&) { return text_response("ok", "text/plain"); });
    REQUIRE(guarded.start().ok());
    httplib::Client client("127.0.0.1", guarded.port());
    auto res = client.Get("/x");
    REQUIRE(res);
    CHECK(res->status == 401);
    CHECK(res->get_header_value("WWW-Authenticate").find("Basic realm=\"test\"") != std::string::npos);
    client.set_basic_auth("ops", "wrong");
    res = client.Get("/x");
    REQUIRE(res);
    CHECK(res->status == 401);
    client.set_basic_auth("ops", "s3cret");
    res = client.Get("/x");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(res->body == "ok");
}

TEST_CASE("http security: Basic credentials are parsed, anything else is none") {
    CHECK(parse_basic_authorization("Basic b3BzOnMzY3JldA==") == std::make_pair(std::string("ops"), std::string("s3cret")));
    CHECK(parse_basic_authorization("basic   b3BzOnMzY3JldA==  ") == std::make_pair(std::string("ops"), std::string("s3cret")));
    CHECK(parse_basic_authorization("Basic b3BzOjp4") == std::make_pair(std::string("ops"), std::string(":x")));
    CHECK_FALSE(parse_basic_authorization("Bearer abc"));
    CHECK_FALSE(parse_basic_authorization("Basic !!!"));
    CHECK_FALSE(parse_basic_authorization("Basic bm9jb2xvbg=="));  // "nocolon"
    CHECK_FALSE(parse_basic_authorization(""));
}

TEST_CASE("http security: a write whose Origin is another site is refused, the same site's passes") {
    HttpServer server(small_options());
    server.post("/set", [](const HttpRequest&) { return text_response("done", "text/plain"); });
    REQUIRE(server.start().ok());
    httplib::Client client("127.0.0.1", server.port());
    const std::string self = "http://127.0.0.1:" + std::to_string(server.port());
    auto res = client.Post("/set", httplib::Headers{{"Origin", "http://evil.example"}}, "{}", "application/json");
    REQUIRE(res);
    CHECK(res->status == 403);
    res = client.Post("/set", httplib::Headers{{"Origin", self}}, "{}", "application/json");
    REQUIRE(res);
    CHECK(res->status == 200);
    res = client.Post("/set", "{}", "application/json");  // no Origin: not a browser's cross-site request
    REQUIRE(res);
    CHECK(res->status == 200);
}

TEST_CASE("http metrics: requests by route and status, latency by route, valid Prometheus text") {
    HttpMetrics metrics;
    HttpServer server(small_options());
    server.set_observer(metrics.observer());
    server.get("/devices/{dev}", [](const HttpRequest&) { return text_response("d", "text/plain"); });
    REQUIRE(server.start().ok());
    httplib::Client client("127.0.0.1", server.port());
    REQUIRE(client.Get("/devices/a"));
    REQUIRE(client.Get("/devices/b"));
    REQUIRE(client.Get("/nothing"));
    REQUIRE(client.Post("/devices/a", "x", "text/plain"));
    server.stop();
    core_detail::PrometheusText out;
    metrics.render(out, "nclink_test");
    const std::string text = out.str();
    INFO(text);
    std::vector<test::PromSample> samples;
    CHECK(test::exposition_problems(text, &samples).empty());
    if (const auto said = test::promtool_problems(text)) {
        INFO(*said);
        CHECK(said->empty());
    }
    // Routes are patterns: the label set stays bounded whatever the paths.
    CHECK(test::prom_value(samples, "nclink_test_http_requests_total",
                           {{"method", "GET"}, {"route", "/devices/{dev}"}, {"code", "200"}}) == 2.0);
    CHECK(test::prom_value(samples, "nclink_test_http_requests_total", {{"method", "GET"}, {"route", ""}, {"code", "404"}}) == 1.0);
    CHECK(test::prom_value(samples, "nclink_test_http_requests_total", {{"method", "POST"}, {"route", ""}, {"code", "405"}}) == 1.0);
    CHECK(test::prom_value(samples, "nclink_test_http_request_duration_seconds_count", {{"route", "/devices/{dev}"}}) == 2.0);
}

TEST_CASE("metrics endpoint: GET /metrics only, small bodies, HOST:PORT checked") {
    auto endpoint = MetricsEndpoint::start(
        "127.0.0.1:0", [] { return std::string("# TYPE x_total counter\nx_total 1\n"); }, "nclink_test", std::nullopt, Logger{});
    REQUIRE(endpoint.ok());
    httplib::Client client("127.0.0.1", endpoint.value()->port());
    auto res = client.Get("/metrics");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(res->get_header_value("Content-Type") == "text/plain; version=0.0.4; charset=utf-8");
    CHECK_THAT(res->body, Catch::StartsWith("# TYPE x_total counter\nx_total 1\n"));
    CHECK(test::exposition_problems(res->body).empty());
    res = client.Get("/metrics");  // the first scrape is counted in the second
    REQUIRE(res);
    CHECK_THAT(res->body, Catch::Contains("nclink_test_http_requests_total{method=\"GET\",route=\"/metrics\",code=\"200\"} 1"));
    res = client.Post("/metrics", "x", "text/plain");
    REQUIRE(res);
    CHECK(res->status == 405);
    res = client.Get("/");
    REQUIRE(res);
    CHECK(res->status == 404);
    res = client.Post("/metrics", std::string(4096, 'x'), "text/plain");
    REQUIRE(res);
    CHECK(res->status == 413);

    CHECK_FALSE(MetricsEndpoint::start(
                    "0.0.0.0:0", [] { return std::string(); }, "p", std::nullopt, Logger{})
                    .ok());
    CHECK_FALSE(parse_listen_address("nohost").ok());
    CHECK_FALSE(parse_listen_address("h:99999").ok());
    CHECK_FALSE(parse_listen_address(":80").ok());
    CHECK(parse_listen_address("[::1]:9464").value() == std::make_pair(std::string("::1"), 9464));
}
