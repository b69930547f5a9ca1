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
    f.clock->advance(35ms);         // ticks 1, 2 missed; tick 3 is read (5 ms late)
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
    f.clock->advance(1000ms);       // 100 ticks due
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

TEST_CASE("missed ticks are logged at most once per overrun_log_interval over all channels") {
    auto lines = std::make_shared<std::vector<std::string>>();
    auto mutex = std::make_shared<std::mutex>();
    SamplingConfig config;
    config.overrun_log_interval = 1000ms;
    EngineFixture f(config);
    // The fixture's engine logs nowhere: build one that logs into `lines`.
    sampling_detail::EngineDeps deps;
    deps.driver = f.runner.get();
    deps.clock = f.clock;
    deps.sleeper = f.sleeper;
    deps.config = config;
    deps.dev = "dev1";
    deps.sink = [](Message) {};
    deps.logger = Logger(
        [lines, mutex](LogLevel level, std::string_view text) {
            if (level < LogLevel::warn) return;
            std::lock_guard<std::mutex> lock(*mutex);
            lines->emplace_back(text);
        },
        LogLevel::debug);
    sampling_detail::SamplingEngine engine(std::move(deps));
    for (const char* id : {"a", "b", "c"}) REQUIRE(engine.add_channel(EngineFixture::spec(id, {id}, 10, 100)).ok());
    engine.run_sampling_once();
    const auto hiccup = [&] {  // every channel misses 2 ticks, then catches up
        f.clock->advance(30ms);
        engine.run_sampling_once();
        f.clock->advance(10ms);
        engine.run_sampling_once();
    };
    hiccup();
    CHECK(lines->size() == 1);  // one line, not one per channel
    for (int i = 0; i < 5; ++i) hiccup();
    CHECK(lines->size() == 1);  // 200 ms later: still quiet
    f.clock->advance(1000ms);
    engine.run_sampling_once();  // a long stall starts a burst after the interval
    REQUIRE(lines->size() == 2);
    CHECK_THAT(lines->back(), Catch::Contains("since the last report"));
    CHECK_THAT(lines->back(), Catch::Contains("on 3 channel(s)"));
}
