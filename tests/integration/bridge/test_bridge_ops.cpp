// What an operator uses on the bridge's HTTP port: the dashboard page, the
// health JSON, /metrics (valid Prometheus text that follows the machine),
// authentication when bound beyond loopback. mosquitto, the simulated mill's
// adapter and the bridge in-process; a real HTTP client.
#include "bridge/bridge.hpp"

#include "support/mosquitto_broker.hpp"
#include "support/prometheus_check.hpp"
#include "support/rig.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>
#include <httplib.h>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;

namespace {

const std::string kDev = nclink::test::kSimMillDevice;

struct OpsRig {
    explicit OpsRig(bridge::BridgeConfig c = {}) {
        AdapterConfig a;
        a.model_path = nclink::test::sim_mill_path();
        a.broker_url = broker.url();
        a.register_timeout = 500ms;
        adapter = nclink::test::started_adapter(a, nclink::test::sim_for(nclink::test::sim_mill_path()));
        c.broker_url = broker.url();
        c.http_port = 0;
        c.shdr_enabled = false;
        c.poll_interval = 200ms;
        c.heartbeat = 500ms;
        c.ex_cid = "bridge-ops-itest";
        the_bridge = std::make_unique<bridge::Bridge>(c, Logger{});
        REQUIRE(the_bridge->start().ok());
        http = std::make_unique<httplib::Client>("127.0.0.1", the_bridge->http_port());
        http->set_read_timeout(10, 0);
        if (!c.http_username.empty()) http->set_basic_auth(c.http_username.c_str(), c.http_password.c_str());
    }
    test::MosquittoBroker broker;
    std::unique_ptr<Adapter> adapter;
    std::unique_ptr<bridge::Bridge> the_bridge;
    std::unique_ptr<httplib::Client> http;
};

}  // namespace

TEST_CASE("bridge ops: the dashboard page, health and metrics that follow the machine") {
    OpsRig rig;
    auto page = rig.http->Get("/dashboard");
    REQUIRE(page);
    CHECK(page->status == 200);
    CHECK(page->get_header_value("Content-Type") == "text/html; charset=utf-8");
    CHECK_THAT(page->get_header_value("Content-Security-Policy"), Catch::Contains("default-src 'self'"));
    // The page follows the JSON API's Server-Sent Events stream.
    CHECK_THAT(page->body, Catch::Contains("<title>nclink dashboard</title>") && Catch::Contains("const api = \"/nclink/v1/\"") &&
                               Catch::Contains("new EventSource(api + \"stream\")"));
    CHECK(rig.http->Get("/dashboard/")->status == 200);
    CHECK(rig.http->Post("/dashboard", "x", "text/plain")->status == 405);

    REQUIRE(eventually(
        [&] {
            auto h = rig.http->Get("/nclink/v1/health");
            if (!h || h->status != 200) return false;
            const Json health = Json::parse(h->body, nullptr, false);
            return health.is_object() && health.value("devices_online", 0) == 1 && health.value("broker", "") == "connected";
        },
        30s));

    std::vector<test::PromSample> samples;
    std::string text;
    REQUIRE(eventually(
        [&] {
            auto m = rig.http->Get("/metrics");
            if (!m || m->status != 200) return false;
            text = m->body;
            samples.clear();
            (void)test::exposition_problems(text, &samples);
            return test::prom_value(samples, "nclink_bridge_devices", {{"state", "online"}}) == 1.0 &&
                   test::prom_value(samples, "nclink_bridge_observations_total").value_or(0) > 0;
        },
        30s));
    INFO(text);
    const auto problems = test::exposition_problems(text);
    for (const auto& p : problems) UNSCOPED_INFO(p);
    CHECK(problems.empty());
    if (const auto said = test::promtool_problems(text)) {
        INFO("promtool: " << *said);
        CHECK(said->empty());
    }
    CHECK(test::prom_value(samples, "nclink_bridge_mqtt_connected") == 1.0);
    CHECK(test::prom_value(samples, "nclink_bridge_dtus_sent_total", {{"kind", "request"}}).value_or(0) >= 1.0);
    CHECK(test::prom_value(samples, "nclink_bridge_http_requests_total",
                           {{"method", "GET"}, {"route", "/dashboard"}, {"code", "200"}}) == 2.0);
    CHECK(test::prom_value(samples, "nclink_bridge_http_requests_total", {{"method", "POST"}, {"route", ""}, {"code", "405"}}) ==
          1.0);
    // The connection gate's counters (docs/metrics.md "HTTP connections").
    CHECK(test::prom_value(samples, "nclink_bridge_http_connections_accepted_total").value_or(0) >= 1.0);
    CHECK(test::prom_value(samples, "nclink_bridge_http_connections_refused_total", {{"cap", "per_peer"}}) == 0.0);
    CHECK(test::prom_value(samples, "nclink_bridge_http_connections_closed_total", {{"reason", "header_timeout"}}) == 0.0);
    CHECK(test::prom_value(samples, "nclink_bridge_http_streams") == 0.0);
}

TEST_CASE("bridge ops: beyond loopback only with credentials, and then every request needs them") {
    bridge::BridgeConfig open;
    open.http_host = "0.0.0.0";
    open.http_port = 0;
    open.shdr_enabled = false;
    open.broker_url = "tcp://127.0.0.1:9";
    bridge::Bridge refused(open, Logger{});
    const auto started = refused.start();
    REQUIRE_FALSE(started.ok());
    CHECK_THAT(started.error().message, Catch::Contains("loopback"));

    bridge::BridgeConfig guarded;
    guarded.http_host = "0.0.0.0";
    guarded.http_username = "operator";
    guarded.http_password = "pw";
    OpsRig rig(guarded);
    CHECK(rig.http->Get("/metrics")->status == 200);
    httplib::Client anonymous("127.0.0.1", rig.the_bridge->http_port());
    for (const char* path : {"/dashboard", "/metrics", "/nclink/v1/devices", "/probe"}) {
        INFO(path);
        auto r = anonymous.Get(path);
        REQUIRE(r);
        CHECK(r->status == 401);
    }
    auto set = anonymous.Post(("/nclink/v1/devices/" + kDev + "/set").c_str(), R"({"id":"spindle_override","value":90})",
                              "application/json");
    REQUIRE(set);
    CHECK(set->status == 401);
}

TEST_CASE("bridge ops: http_username and http_password are configuration keys") {
    auto c = bridge::bridge_config_from_json(Json{{"http", "0.0.0.0:5000"}, {"http_username", "u"}, {"http_password", "p"}});
    REQUIRE(c.ok());
    CHECK(c->http_username == "u");
    CHECK(c->http_password == "p");
    CHECK_FALSE(bridge::bridge_config_from_json(Json{{"http_user", "u"}}).ok());
}
