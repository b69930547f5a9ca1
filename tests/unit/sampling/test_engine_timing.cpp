// Timing policy of the sampling engine, on fake time: absolute deadlines,
// late and missed ticks, overruns, failing reads, long stalls.
#include "engine_fixture.hpp"

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("absolute deadlines do not drift when every wake-up is late") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 10, 100)).ok());
    f.engine->run_sampling_once();  // tick 0 at t = 0
    // Wake up 3 ms late for every tick, 100 times: a relative timer would
    // drift by 300 ms; absolute deadlines keep tick k at k * 10 ms.
    for (int k = 1; k <= 100; ++k) {
        f.clock->advance(10ms);
        if (k == 1) f.clock->advance(3ms);
        f.engine->run_sampling_once();
        f.engine->run_upload_once();
    }
    f.engine->run_upload_once(true);
    const auto s = f.stats("ch");
    CHECK(s.rows_sampled == 101);
    CHECK(s.overruns == 0);
    CHECK(s.lateness[1] == 0);  // 3 ms late lands in [2000, 5000) us
    CHECK(s.lateness[8] == 100);
    const auto dtus = f.dtus("Sample/dev1/ch");
    REQUIRE(!dtus.empty());
    CHECK(dtus.front().at("beginTime") == "1700000000000");
    const auto cols = f.columns("Sample/dev1/ch");
    REQUIRE(cols.size() == 1);
    CHECK(cols[0].size() == 101);
}

TEST_CASE("rows carry their nominal times: beginTime of each DTU is its first row") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 10, 50)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 40ms);
    f.engine->run_upload_once(true);  // rows 0..4
    f.step(10ms, 50ms);
    f.engine->run_upload_once(true);  // rows 5..9
    const auto dtus = f.dtus("Sample/dev1/ch");
    REQUIRE(dtus.size() == 2);
    CHECK(dtus[0].at("beginTime") == "1700000000000");
    CHECK(dtus[1].at("beginTime") == "1700000000050");
    CHECK(dtus[0].at("data")[0].at("data").size() == 5);
    CHECK(dtus[1].at("data")[0].at("data") == Json::array({6, 7, 8, 9, 10}));
}

TEST_CASE("missed ticks still produce rows with null in every slot and count as overruns") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a", "b"}, 10, 100)).ok());
    f.engine->run_sampling_once();  // tick 0
    f.clock->advance(35ms);          // ticks 1, 2 missed; tick 3 is read (5 ms late)
    f.engine->run_sampling_once();
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    REQUIRE(cols.size() == 2);
    CHECK(cols[0] == std::vector<Json>{1, nullptr, nullptr, 2});
    CHECK(cols[1] == std::vector<Json>{1, nullptr, nullptr, 2});
    const auto s = f.stats("ch");
    CHECK(s.overruns == 2);
    CHECK(s.rows_sampled == 4);
    CHECK(s.null_values == 4);
    CHECK(s.max_lateness_us == 25000);  // tick 1 was due 25 ms before the pass
}

TEST_CASE("a failing read gives null in its own slot and never shifts a column") {
    EngineFixture f;
    f.driver->failing.insert("b");
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a", "b", "c"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 20ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    REQUIRE(cols.size() == 3);
    CHECK(cols[0] == std::vector<Json>{1, 2, 3});
    CHECK(cols[1] == std::vector<Json>{nullptr, nullptr, nullptr});
    CHECK(cols[2] == std::vector<Json>{1, 2, 3});
    CHECK(f.stats("ch").null_values == 3);
    CHECK(f.stats("ch").overruns == 0);
}

TEST_CASE("after a long stall only one upload period of null rows is made and the DTU restarts after the gap") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 10, 50)).ok());
    f.engine->run_sampling_once();  // tick 0
    f.clock->advance(1000ms);        // 100 ticks due
    f.engine->run_sampling_once();
    f.engine->run_upload_once(true);
    const auto s = f.stats("ch");
    CHECK(s.skipped_ticks == 94);  // ticks 1..94 skipped, 95..99 null, 100 read
    CHECK(s.overruns == 5);
    CHECK(s.rows_sampled == 7);
    const auto dtus = f.dtus("Sample/dev1/ch");
    REQUIRE(dtus.size() == 2);  // tick 0 alone; ticks 95..100 after the gap
    CHECK(dtus[0].at("data")[0].at("data") == Json::array({1}));
    CHECK(dtus[1].at("beginTime") == "1700000000950");
    CHECK(dtus[1].at("data")[0].at("data") == Json::array({nullptr, nullptr, nullptr, nullptr, nullptr, 2}));
}

TEST_CASE("ticks are served only when due") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.clock->advance(9ms);
    f.engine->run_sampling_once();
    CHECK(f.stats("ch").rows_sampled == 1);
    f.clock->advance(1ms);
    f.engine->run_sampling_once();
    CHECK(f.stats("ch").rows_sampled == 2);
    CHECK(f.driver->reads == 2);
}

TEST_CASE("fractional sample intervals keep exact nominal spacing") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 0.5, 10)).ok());
    f.engine->run_sampling_once();
    f.step(500us, 10ms);
    CHECK(f.stats("ch").rows_sampled == 21);
    CHECK(f.stats("ch").overruns == 0);
}
