// The connection gate's counters reach a program's /metrics (docs/metrics.md
// "HTTP connections"): each one is provoked by raw peers and read back from
// the Prometheus text, as a scrape sees it. Timeouts are short so the test is
// quick; the checks are counts, never speeds.
#include "core/prometheus_text.hpp"
#include "http/http_metrics.hpp"
#include "http/http_server.hpp"
#include "http/metrics_endpoint.hpp"

#include "support/prometheus_check.hpp"
#include "support/raw_peer.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

using namespace nclink;
using namespace nclink::http;
using namespace std::chrono_literals;
using nclink::test::RawPeer;

namespace {

// The body of GET /metrics, or nothing when the connection was refused or
// closed before an answer (a slot the server has not yet seen freed).
std::optional<std::string> try_get_metrics(int port) {
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(5s);
    auto res = client.Get("/metrics");
    if (!res || res->status != 200) return std::nullopt;
    return res->body;
}

std::vector<test::PromSample> parse_scrape(const std::string& body) {
    std::vector<test::PromSample> samples;
    const auto problems = test::exposition_problems(body, &samples);
    INFO(body);
    for (const auto& p : problems) UNSCOPED_INFO(p);
    CHECK(problems.empty());
    return samples;
}

std::vector<test::PromSample> scrape(int port, std::string* text_out = nullptr) {
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(5s);
    auto res = client.Get("/metrics");
    REQUIRE(res);
    REQUIRE(res->status == 200);
    if (text_out) *text_out = res->body;
    return parse_scrape(res->body);
}

double value(const std::vector<test::PromSample>& samples, const std::string& name,
             const std::map<std::string, std::string>& labels = {}) {
    const auto v = test::prom_value(samples, name, labels);
    INFO(name);
    REQUIRE(v.has_value());
    return *v;
}

}  // namespace

TEST_CASE("every connection counter of a program's /metrics is provoked and read from /metrics") {
    EndpointLimits limits;
    // Long enough for the held connections below to do their part first.
    limits.header_timeout = 1500ms;
    limits.keep_alive = 300ms;
    limits.max_connections_per_peer = 2;
    limits.max_connections = 5;
    auto made = MetricsEndpoint::start(
        "127.0.0.1:0", [] { return std::string("# TYPE up gauge\nup 1\n"); }, "nclink_test", std::nullopt, Logger{}, limits);
    REQUIRE(made);
    auto& endpoint = **made;

    {  // half a request line, then nothing: closed by the header deadline
        RawPeer slow(endpoint.port(), "127.0.5.1");
        REQUIRE(slow.send("GET /metr"));
        CHECK(slow.closed_within(5s));
    }
    {  // a whole request, answered, then idle: closed by the keep-alive limit
        RawPeer idle(endpoint.port(), "127.0.5.2");
        REQUIRE(idle.send("GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n"));
        CHECK(idle.receive(5s, 1).rfind("HTTP/1.1 200", 0) == 0);
        CHECK(idle.closed_within(5s));
    }
    std::vector<std::unique_ptr<RawPeer>> held;
    // Three from one address: the third is refused by the per-peer cap.
    for (int i = 0; i < 3; ++i) held.push_back(std::make_unique<RawPeer>(endpoint.port(), "127.0.5.3"));
    CHECK(held.back()->closed_within(2s));
    held.pop_back();
    // Three more from three addresses fill the server (5); a sixth is refused by the total cap.
    for (int i = 0; i < 3; ++i)
        held.push_back(std::make_unique<RawPeer>(endpoint.port(), ("127.0.5." + std::to_string(4 + i)).c_str()));
    auto surplus = std::make_unique<RawPeer>(endpoint.port(), "127.0.5.7");
    CHECK(surplus->closed_within(2s));
    surplus.reset();
    held.clear();

    // The scrape itself needs a free slot: the server may not yet have seen the
    // held connections go (a scrape refused by the total cap is tried again).
    std::vector<test::PromSample> samples;
    int refused_scrapes = 0;
    REQUIRE(test::eventually([&] {
        const auto body = try_get_metrics(endpoint.port());
        if (!body) {
            ++refused_scrapes;
            return false;
        }
        samples = parse_scrape(*body);
        // Only the scrape's own connection, and it has a worker: an earlier
        // scrape's connection may still be in the gate until it sees the close.
        const auto open = test::prom_value(samples, "nclink_test_http_connections_open");
        const auto waiting = test::prom_value(samples, "nclink_test_http_connections_waiting");
        return open && *open == 1.0 && waiting && *waiting == 0.0;
    }));
    CHECK(value(samples, "nclink_test_http_connections_closed_total", {{"reason", "header_timeout"}}) >= 1.0);
    CHECK(value(samples, "nclink_test_http_connections_closed_total", {{"reason", "idle"}}) >= 1.0);
    CHECK(value(samples, "nclink_test_http_connections_refused_total", {{"cap", "per_peer"}}) == 1.0);
    // The surplus peer, and any scrape that came before the server saw the slots freed.
    CHECK(value(samples, "nclink_test_http_connections_refused_total", {{"cap", "total"}}) == 1.0 + refused_scrapes);
    // 1 slow + 1 idle + 2 + 3 held + the scrapes so far (each on its own connection).
    CHECK(value(samples, "nclink_test_http_connections_accepted_total") >= 8.0);
    CHECK(value(samples, "nclink_test_http_connections_waiting") == 0.0);  // the scrape has a worker
    CHECK(value(samples, "nclink_test_http_streams_total") == 0.0);
    CHECK(value(samples, "nclink_test_http_streams_refused_total") == 0.0);
    CHECK(value(samples, "nclink_test_http_streams") == 0.0);
    endpoint.stop();
}

TEST_CASE("the stream counters reach the Prometheus text: begun, refused, running") {
    HttpOptions o;
    o.workers = 2;
    o.max_streams = 2;
    HttpServer server(o);
    HttpMetrics metrics;
    server.set_observer(metrics.observer());
    server.get("/stream", [](const HttpRequest&) {
        HttpResponse r;
        r.content_type = std::string(sse_content_type);
        r.stream = [](StreamSink& sink) {
            SseWriter sse(sink);
            while (sink.sleep_for(10ms))
                if (!sse.comment("beat")) return;
        };
        return r;
    });
    server.get("/metrics", [&](const HttpRequest&) {
        core_detail::PrometheusText out;
        metrics.render(out, "nclink_test");
        HttpMetrics::render(out, "nclink_test", server.connection_counters());
        return text_response(out.str(), std::string(core_detail::prometheus_content_type));
    });
    REQUIRE(server.start().ok());
    std::vector<std::unique_ptr<RawPeer>> readers;
    for (int i = 0; i < 3; ++i) {
        readers.push_back(std::make_unique<RawPeer>(server.port()));
        REQUIRE(readers.back()->send("GET /stream HTTP/1.1\r\nHost: x\r\n\r\n"));
        CHECK(readers.back()->receive(5s, 12).rfind(i < 2 ? "HTTP/1.1 200" : "HTTP/1.1 503", 0) == 0);
    }
    REQUIRE(test::eventually([&] { return server.active_streams() == 2; }));
    auto samples = scrape(server.port());
    CHECK(value(samples, "nclink_test_http_streams_total") == 2.0);
    CHECK(value(samples, "nclink_test_http_streams_refused_total") == 1.0);
    CHECK(value(samples, "nclink_test_http_streams") == 2.0);
    server.stop();
}

TEST_CASE("a metrics endpoint takes its HTTP limits: a per-peer cap of 2 refuses the third connection") {
    EndpointLimits limits;
    limits.max_connections_per_peer = 2;
    auto made = MetricsEndpoint::start(
        "127.0.0.1:0", [] { return std::string("# TYPE up gauge\nup 1\n"); }, "nclink_test", std::nullopt, Logger{}, limits);
    REQUIRE(made);
    std::vector<std::unique_ptr<RawPeer>> peers;
    for (int i = 0; i < 3; ++i) peers.push_back(std::make_unique<RawPeer>((*made)->port(), "127.0.6.1"));
    CHECK(peers[2]->closed_within(2s));
    CHECK_FALSE(peers[0]->closed_within(200ms));
    // Another address is served.
    auto samples = scrape((*made)->port());
    CHECK(value(samples, "nclink_test_http_connections_refused_total", {{"cap", "per_peer"}}) == 1.0);
}
