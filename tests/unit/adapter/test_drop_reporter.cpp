// Every loss is logged once per burst (src/adapter/drop_reporter.hpp).
#include "adapter/drop_reporter.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using nclink::Logger;
using nclink::LogLevel;

namespace {
nclink::feature_detail::DropCounts drops(std::uint64_t offline_buffer_full, std::uint64_t sample_ring_full) {
    nclink::feature_detail::DropCounts d;
    d.add("offline_buffer_full", offline_buffer_full);
    d.add("sample_ring_full", sample_ring_full);
    return d;
}
}  // namespace

TEST_CASE("drop reporter: a warning when a cause starts dropping, one line when the burst is over") {
    std::vector<std::pair<LogLevel, std::string>> lines;
    const Logger logger([&](LogLevel level, std::string_view text) { lines.emplace_back(level, std::string(text)); },
                        LogLevel::debug);
    nclink::adapter_detail::DropReporter reporter(logger);
    reporter.observe(drops(0, 0));
    CHECK(lines.empty());
    reporter.observe(drops(5, 0));
    reporter.observe(drops(50, 0));
    reporter.observe(drops(500, 0));
    REQUIRE(lines.size() == 1);  // once for the burst, however long
    CHECK(lines[0].first == LogLevel::warn);
    CHECK(lines[0].second.find("offline_buffer_full") != std::string::npos);
    reporter.observe(drops(500, 0));
    REQUIRE(lines.size() == 2);
    CHECK(lines[1].first == LogLevel::info);
    CHECK(lines[1].second.find("500 in this burst") != std::string::npos);
    reporter.observe(drops(500, 0));
    CHECK(lines.size() == 2);
    reporter.observe(drops(510, 0));
    REQUIRE(lines.size() == 3);  // a new burst
    reporter.observe(drops(510, 0));
    REQUIRE(lines.size() == 4);
    CHECK(lines[3].second.find("10 in this burst, 510 in all") != std::string::npos);
}

TEST_CASE("drop reporter: counts filled again in place are read as new, and a cause seen late joins") {
    std::vector<std::pair<LogLevel, std::string>> lines;
    const Logger logger([&](LogLevel level, std::string_view text) { lines.emplace_back(level, std::string(text)); },
                        LogLevel::debug);
    nclink::adapter_detail::DropReporter reporter(logger);
    nclink::feature_detail::DropCounts counts;  // as the housekeeping keeps one
    auto look = [&](std::uint64_t ring, std::uint64_t spool) {
        counts.zero();
        counts.add("sample_ring_full", ring);
        if (spool > 0) counts.add("spool_full", spool);
        reporter.observe(counts);
    };
    look(0, 0);
    look(3, 0);
    REQUIRE(lines.size() == 1);
    CHECK(lines[0].second.find("sample_ring_full") != std::string::npos);
    look(3, 7);  // ring quiet: its burst ends; spool starts one
    REQUIRE(lines.size() == 3);
    CHECK(lines[1].second.find("drops (sample_ring_full) stopped: 3 in this burst") != std::string::npos);
    CHECK(lines[2].second.find("spool_full") != std::string::npos);
    CHECK(counts.causes().size() == 2);
}

TEST_CASE("the drops object names the adapter's causes and every feature's") {
    nclink::feature_detail::DropCounts features;
    features.add("sample_ring_full", 4);
    const auto json = nclink::adapter_detail::drops_by_cause(features, 2, 1);
    CHECK(json == nclink::Json{{"offline_buffer_full", 2}, {"requests_shed", 1}, {"sample_ring_full", 4}});
}
