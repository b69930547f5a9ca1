// Every loss is logged once per burst (src/adapter/drop_reporter.hpp).
#include "adapter/drop_reporter.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using nclink::Json;
using nclink::Logger;
using nclink::LogLevel;

TEST_CASE("drop reporter: a warning when a cause starts dropping, one line when the burst is over") {
    std::vector<std::pair<LogLevel, std::string>> lines;
    const Logger logger([&](LogLevel level, std::string_view text) { lines.emplace_back(level, std::string(text)); },
                        LogLevel::debug);
    nclink::adapter_detail::DropReporter reporter(logger);
    reporter.observe(Json{{"offline_buffer_full", 0}, {"sample_ring_full", 0}});
    CHECK(lines.empty());
    reporter.observe(Json{{"offline_buffer_full", 5}, {"sample_ring_full", 0}});
    reporter.observe(Json{{"offline_buffer_full", 50}, {"sample_ring_full", 0}});
    reporter.observe(Json{{"offline_buffer_full", 500}, {"sample_ring_full", 0}});
    REQUIRE(lines.size() == 1);  // once for the burst, however long
    CHECK(lines[0].first == LogLevel::warn);
    CHECK(lines[0].second.find("offline_buffer_full") != std::string::npos);
    reporter.observe(Json{{"offline_buffer_full", 500}, {"sample_ring_full", 0}});
    REQUIRE(lines.size() == 2);
    CHECK(lines[1].first == LogLevel::info);
    CHECK(lines[1].second.find("500 in this burst") != std::string::npos);
    reporter.observe(Json{{"offline_buffer_full", 500}, {"sample_ring_full", 0}});
    CHECK(lines.size() == 2);
    reporter.observe(Json{{"offline_buffer_full", 510}, {"sample_ring_full", 0}});
    REQUIRE(lines.size() == 3);  // a new burst
    reporter.observe(Json{{"offline_buffer_full", 510}, {"sample_ring_full", 0}});
    REQUIRE(lines.size() == 4);
    CHECK(lines[3].second.find("10 in this burst, 510 in all") != std::string::npos);
}
