#include "core/latency_histogram.hpp"
#include "core/prometheus_text.hpp"

#include "support/prometheus_check.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::core_detail;
using nclink::test::exposition_problems;
using nclink::test::prom_value;
using nclink::test::PromSample;

namespace {
std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}
}  // namespace

TEST_CASE("prometheus text: a family is HELP, TYPE and its samples together, whatever the order of adding") {
    PrometheusText t;
    t.counter("nclink_x_total", "X things", {{"dev", "a"}}, std::uint64_t{1});
    t.gauge("nclink_y", "Y now", {}, 2.5);
    t.counter("nclink_x_total", "X things", {{"dev", "b"}}, std::uint64_t{3});
    CHECK(t.str() ==
          "# HELP nclink_x_total X things\n# TYPE nclink_x_total counter\n"
          "nclink_x_total{dev=\"a\"} 1\nnclink_x_total{dev=\"b\"} 3\n"
          "# HELP nclink_y Y now\n# TYPE nclink_y gauge\nnclink_y 2.5\n");
    CHECK(exposition_problems(t.str()).empty());
}

TEST_CASE("prometheus text: label values escape backslash, quote and line feed, and bad UTF-8 becomes ?") {
    CHECK(escape_label_value("a\\b\"c\nd") == "a\\\\b\\\"c\\nd");
    CHECK(escape_label_value("轴") == "轴");
    CHECK(escape_label_value(std::string("x\xff\xc3y")) == "x??y");
    PrometheusText t;
    t.gauge("nclink_g", "help with \\ and\nline", {{"id", "we\"ird\\id\n"}}, 1);
    std::vector<PromSample> samples;
    INFO(t.str());
    CHECK(exposition_problems(t.str(), &samples).empty());
    CHECK(prom_value(samples, "nclink_g", {{"id", "we\"ird\\id\n"}}) == 1);
}

TEST_CASE("prometheus text: values are exact integers, shortest decimals, +Inf, -Inf and NaN") {
    CHECK(format_metric_value(3) == "3");
    CHECK(format_metric_value(0.25) == "0.25");
    CHECK(format_metric_value(1e20) == "1e+20");
    CHECK(format_metric_value(HUGE_VAL) == "+Inf");
    CHECK(format_metric_value(-HUGE_VAL) == "-Inf");
    CHECK(format_metric_value(std::nan("")) == "NaN");
}

TEST_CASE("prometheus text: a histogram is cumulative with +Inf, _sum and _count") {
    HistogramSnapshot h;
    h.upper_bounds = {0.1, 1};
    h.counts = {2, 3, 4};
    h.sum = 7.5;
    PrometheusText t;
    t.histogram("nclink_h_seconds", "H", {{"kind", "query"}}, h);
    CHECK(t.str() ==
          joined({"# HELP nclink_h_seconds H", "# TYPE nclink_h_seconds histogram",
                  "nclink_h_seconds_bucket{kind=\"query\",le=\"0.1\"} 2", "nclink_h_seconds_bucket{kind=\"query\",le=\"1\"} 5",
                  "nclink_h_seconds_bucket{kind=\"query\",le=\"+Inf\"} 9", "nclink_h_seconds_sum{kind=\"query\"} 7.5",
                  "nclink_h_seconds_count{kind=\"query\"} 9"}));
    CHECK(exposition_problems(t.str()).empty());
}

TEST_CASE("prometheus text: a declared family without samples still has HELP and TYPE") {
    PrometheusText t;
    t.declare("nclink_d_total", "counter", "nothing yet");
    CHECK(t.str() == "# HELP nclink_d_total nothing yet\n# TYPE nclink_d_total counter\n");
    CHECK(exposition_problems(t.str()).empty());
}

TEST_CASE("latency histogram: each observation lands in the first bucket whose bound it does not exceed") {
    LatencyHistogram h;
    h.observe(std::chrono::microseconds(100));  // exactly the first bound
    h.observe(std::chrono::microseconds(101));  // the second
    h.observe(std::chrono::seconds(60));        // above every bound
    h.observe(std::chrono::nanoseconds(-5));    // a clock step back counts as 0
    const auto s = h.snapshot();
    REQUIRE(s.counts.size() == kLatencyBoundsSeconds.size() + 1);
    CHECK(s.counts[0] == 2);
    CHECK(s.counts[1] == 1);
    CHECK(s.counts.back() == 1);
    CHECK(s.count == 4);
    CHECK(s.sum == Approx(60.000201));
    PrometheusText t;
    t.histogram("nclink_l_seconds", "L", {}, s);
    CHECK(exposition_problems(t.str()).empty());
}

TEST_CASE("the format checker of the tests finds what is wrong") {
    // (the checker guards every metrics test: it must not pass everything)
    CHECK_FALSE(exposition_problems("x 1\n").empty());                                       // no TYPE
    CHECK_FALSE(exposition_problems("# TYPE x_total counter\nx_total{a=\"1} 1\n").empty());  // quote
    CHECK_FALSE(exposition_problems("# TYPE x counter\nx 1\n").empty());                     // _total
    CHECK_FALSE(exposition_problems("# TYPE a gauge\na 1\n# TYPE b gauge\nb 1\na{x=\"1\"} 2\n").empty());
    CHECK_FALSE(
        exposition_problems("# TYPE h histogram\nh_bucket{le=\"1\"} 3\nh_bucket{le=\"+Inf\"} 2\nh_sum 1\nh_count 2\n").empty());
    CHECK_FALSE(exposition_problems("# TYPE h histogram\nh_bucket{le=\"1\"} 3\nh_sum 1\nh_count 3\n").empty());
    CHECK_FALSE(exposition_problems("# TYPE 1x gauge\n1x 1\n").empty());
    CHECK(exposition_problems("# TYPE g gauge\ng{a=\"\\\\\"} -Inf\n").empty());
}
