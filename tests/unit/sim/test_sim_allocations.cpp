// The simulated mill reads its sampled items without a heap allocation once
// warm (SimDriver::read_samples): the sampling path of an adapter on the
// simulator is then free of allocations per row end to end, as
// bench_footprint measures it (docs/footprint.md). Before, every text value
// (status, program, ...) went through a JSON string: about 50 allocations a
// second on the sampler thread of nclink-sim.
//
// Counted by support/counting_new.hpp (a counter in front of malloc).
#include "sim_test_util.hpp"
#include "support/counting_new.hpp"

TEST_CASE("the mill's sampled items, texts included, are read without an allocation per row") {
    sim_test::Rig rig("sim-mill.json", 7);
    // Both channels of models/sim-mill.json: numbers, and texts (status,
    // work mode, program, line number, part count).
    const std::vector<std::string> ids{"x_position", "y_position",    "z_position",   "x_speed",          "y_speed",
                                       "z_speed",    "spindle_speed", "spindle_load", "spindle_override", "status",
                                       "work_mode",  "program",       "line_number",  "part_count"};
    std::vector<nclink::PointRef> points;
    for (const auto& id : ids) points.push_back({id, nclink::DataKind::single});
    std::vector<nclink::SampleValue> row(points.size());
    for (int warm = 0; warm < 20; ++warm) {
        rig.advance_ms(100);
        REQUIRE(rig.driver->read_samples(points, row.data()));
    }
    bool saw_text = false;
    for (const auto& v : row) saw_text = saw_text || v.kind() == nclink::SampleValue::Kind::text;
    CHECK(saw_text);

    g_allocations = 0;
    for (int i = 0; i < 500; ++i) {
        rig.advance_ms(10);
        g_counting = true;
        const bool read = rig.driver->read_samples(points, row.data());
        g_counting = false;
        REQUIRE(read);
    }
    if (!NCLINK_TEST_COUNTS_ALLOCATIONS) {
        WARN("allocations not counted under a sanitizer");
        return;
    }
    CHECK(g_allocations.load() == 0);
}
