#include "support/adapter_fixture.hpp"

#include "adapter/adapter_metrics.hpp"
#include "support/prometheus_check.hpp"

#include <nclink/adapter_metrics.hpp>

using namespace nclink;
using namespace nclink::test;

namespace {

void check_format(const std::string& text) {
    INFO(text);
    const auto problems = exposition_problems(text);
    for (const auto& p : problems) UNSCOPED_INFO(p);
    CHECK(problems.empty());
    if (const auto said = promtool_problems(text)) {
        INFO("promtool check metrics: " << *said);
        CHECK(said->empty());
    } else {
        WARN(
            "promtool not installed (Debian package prometheus; NCLINK_WITH_PROMETHEUS=1 tools/install-deps.sh): "
            "the format checked by the test's own reader only");
    }
}

}  // namespace

TEST_CASE("adapter metrics: DTUs by kind and request latency of a running adapter, in valid Prometheus text") {
    AdapterFixture f;
    f.query(Json::array({"pos"}));
    f.set(Json{{"ovr", 90}});
    std::vector<PromSample> samples;
    REQUIRE(eventually([&] {
        samples.clear();
        (void)exposition_problems(prometheus_metrics(*f.adapter), &samples);
        const auto set_count =
            prom_value(samples, "nclink_adapter_request_duration_seconds_count", {{"dev", "test-dev"}, {"kind", "set_request"}});
        return set_count && *set_count >= 1;
    }));
    const std::string text = prometheus_metrics(*f.adapter);
    check_format(text);
    CHECK(prom_value(samples, "nclink_adapter_dtus_received_total", {{"dev", "test-dev"}, {"kind", "query_request"}}) >= 1.0);
    CHECK(prom_value(samples, "nclink_adapter_dtus_sent_total", {{"dev", "test-dev"}, {"kind", "query_response"}}) >= 1.0);
    CHECK(prom_value(samples, "nclink_adapter_dtus_sent_total", {{"dev", "test-dev"}, {"kind", "register_request"}}) >= 1.0);
    CHECK(prom_value(samples, "nclink_adapter_request_duration_seconds_count", {{"dev", "test-dev"}, {"kind", "query_request"}}) >=
          1.0);
    CHECK(prom_value(samples, "nclink_adapter_state", {{"dev", "test-dev"}, {"state", "normal"}}) == 1.0);
    CHECK(prom_value(samples, "nclink_adapter_requests_total", {{"dev", "test-dev"}}) >= 2.0);
    const auto traffic = f.adapter->traffic_stats();
    CHECK(traffic.dtus_in.at("set_request") >= 1);
}

TEST_CASE("adapter metrics: drops by cause, spool, sampling lateness, events and methods from known statistics") {
    AdapterStats s;
    s.state = AdapterState::disconnected;
    s.transport.dropped = 7;
    s.features = Json{
        {"sampling", {{"spool", {{"dropped", 3}, {"pending", 12}, {"memory_bytes", 4096}, {"disk_bytes", 0}, {"replayed", 5}}}}},
        {"events", {{"dropped_values", 2}, {"registered", 4}, {"fired", 9}}},
        {"methods", {{"running", 1}, {"accepted", 6}, {"finished", 4}, {"canceled", 1}, {"errors", 1}, {"rejected_calls", 2}}}};
    SamplingStats sampling;
    sampling.running = true;
    ChannelStats c;
    c.id = "axes";
    c.sample_interval_ms = 1;
    c.drops = 11;
    c.lateness[0] = 5;      // under 10 us
    c.lateness[3] = 2;      // 50..100 us
    c.lateness.back() = 1;  // over 100 ms
    sampling.channels.push_back(c);
    TrafficStats traffic;
    traffic.dtus_in["query_request"] = 3;
    core_detail::PrometheusText out;
    adapter_detail::add_adapter_metrics(out, "m\"1", s, sampling, traffic);
    const std::string text = out.str();
    check_format(text);
    std::vector<PromSample> samples;
    (void)exposition_problems(text, &samples);
    auto drops = [&](const char* cause) {
        return prom_value(samples, "nclink_adapter_drops_total", {{"dev", "m\"1"}, {"cause", cause}});
    };
    CHECK(drops("outbox_full") == 7.0);
    CHECK(drops("ring_full") == 11.0);
    CHECK(drops("spool_full") == 3.0);
    CHECK(drops("event_inbox_full") == 2.0);
    CHECK(prom_value(samples, "nclink_adapter_spool_dtus", {{"dev", "m\"1"}}) == 12.0);
    CHECK(prom_value(samples, "nclink_adapter_state", {{"dev", "m\"1"}, {"state", "disconnected"}}) == 1.0);
    const std::map<std::string, std::string> ch{{"dev", "m\"1"}, {"channel", "axes"}};
    auto bucket = [&](const char* le) {
        auto l = ch;
        l["le"] = le;
        return prom_value(samples, "nclink_adapter_sampling_lateness_seconds_bucket", l);
    };
    CHECK(bucket("1e-05") == 5.0);
    CHECK(bucket("0.0001") == 7.0);
    CHECK(bucket("0.1") == 7.0);
    CHECK(bucket("+Inf") == 8.0);
    CHECK(prom_value(samples, "nclink_adapter_method_results_total", {{"dev", "m\"1"}, {"result", "finished"}}) == 4.0);
    CHECK(prom_value(samples, "nclink_adapter_events_fired_total", {{"dev", "m\"1"}}) == 9.0);
}

TEST_CASE("adapter metrics: a list of adapters skips null entries") {
    AdapterFixture f;
    const std::string text = prometheus_metrics(std::vector<const Adapter*>{nullptr, f.adapter.get()});
    check_format(text);
}
