#include "unit/agent/agent_fixture.hpp"

#include "support/prometheus_check.hpp"

#include <nclink/agent_metrics.hpp>

using namespace nclink;
using namespace nclink::test;

TEST_CASE("agent metrics: registrations by outcome, terminals and DTUs by kind, in valid Prometheus text") {
    AgentFixture f;
    CHECK(f.register_as(*f.app, "mill-1", "r1")["code"] == "OK");
    CHECK(f.register_as(*f.app, "bad id", "r2")["code"] == "NG");
    const std::string text = prometheus_metrics(*f.agent);
    INFO(text);
    std::vector<PromSample> samples;
    const auto problems = exposition_problems(text, &samples);
    for (const auto& p : problems) UNSCOPED_INFO(p);
    CHECK(problems.empty());
    if (const auto said = promtool_problems(text)) {
        INFO("promtool check metrics: " << *said);
        CHECK(said->empty());
    } else {
        WARN("promtool not installed (Debian package prometheus): the format checked by the test's own reader only");
    }
    CHECK(prom_value(samples, "nclink_agent_registrations_total", {{"outcome", "accepted"}}) == 1.0);
    CHECK(prom_value(samples, "nclink_agent_registrations_total", {{"outcome", "refused"}}) == 1.0);
    CHECK(prom_value(samples, "nclink_agent_dtus_received_total", {{"kind", "register_request"}}) >= 2.0);
    CHECK(prom_value(samples, "nclink_agent_dtus_sent_total", {{"kind", "register_response"}}) >= 2.0);
    double registered = 0;
    for (const char* kind : {"adapter", "application", "unknown"})
        registered += prom_value(samples, "nclink_agent_registered_terminals", {{"kind", kind}}).value_or(0);
    CHECK(registered == 1.0);
}
