// Channels of the sampling engine: DTU shape, ring full policies, one
// sampling thread for all channels, add/remove while running, SDK-held
// items, text values, the sample tap, statistics.
#include "engine_fixture.hpp"

#include "adapter/model_host.hpp"
#include "sampling/spsc_ring.hpp"

#include <nclink/model.hpp>

#include <limits>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("the Sample DTU has one data column per channel id in the channel order") {
    EngineFixture f;
    f.driver->counters["x"] = 100;
    f.driver->counters["z"] = 300;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("cn1", {"z", "x", "y"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 90ms);
    f.engine->run_upload_once(true);
    const auto dtus = f.dtus("Sample/dev1/cn1");
    REQUIRE(dtus.size() == 1);
    const auto& d = dtus[0];
    CHECK(d.at("guid") == "dev1");
    CHECK(d.at("id") == "cn1");
    CHECK(d.at("beginTime").is_string());
    REQUIRE(d.at("data").size() == 3);
    CHECK(d.at("data")[0].at("data") == Json::array({301, 302, 303, 304, 305, 306, 307, 308, 309, 310}));
    CHECK(d.at("data")[1].at("data") == Json::array({101, 102, 103, 104, 105, 106, 107, 108, 109, 110}));
    CHECK(d.at("data")[2].at("data") == Json::array({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
    // decodes with the protocol's own codec
    auto decoded = decode<SampleDtu>(f.sent.at(0).payload);
    REQUIRE(decoded.ok());
}

TEST_CASE("the uploader publishes each channel every uploadInterval") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("fast", {"a"}, 1, 10)).ok());
    REQUIRE(f.engine->add_channel(EngineFixture::spec("slow", {"b"}, 10, 50)).ok());
    f.engine->run_sampling_once();
    f.engine->run_upload_once();
    for (int ms = 1; ms <= 100; ++ms) {
        f.clock->advance(1ms);
        f.engine->run_sampling_once();
        f.engine->run_upload_once();
    }
    CHECK(f.dtus("Sample/dev1/fast").size() == 10);
    CHECK(f.dtus("Sample/dev1/slow").size() == 2);
    const auto s = f.stats("fast");
    CHECK(s.rows_published == 101);  // each pass samples before it uploads: tick 100 made the 10th DTU
    CHECK(s.dtus_published == 10);
}

TEST_CASE("drop_oldest: a full ring loses and counts the oldest rows and the DTU begins at the first kept row") {
    SamplingConfig config;
    config.ring_periods = 1;
    config.ring_min_ms = 64;  // capacity 64 rows of 1 ms
    EngineFixture f(config);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 1, 10)).ok());
    f.engine->run_sampling_once();
    f.step(1ms, 99ms);  // 100 rows, no upload: 36 dropped
    const auto s = f.stats("ch");
    CHECK(s.ring_capacity == 64);
    CHECK(s.drops == 36);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    REQUIRE(cols[0].size() == 64);
    CHECK(cols[0].front() == 37);
    CHECK(cols[0].back() == 100);
    CHECK(f.dtus("Sample/dev1/ch").front().at("beginTime") == "1700000000036");
}

TEST_CASE("block: a full ring holds the sampler back and the ticks it missed become null rows") {
    SamplingConfig config;
    config.ring_periods = 1;
    config.ring_min_ms = 64;  // 64 rows of 1 ms
    config.full_policy = "block";
    EngineFixture f(config);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 1, 10)).ok());
    f.engine->run_sampling_once();
    f.step(1ms, 69ms);  // 70 ticks due, 64 fit
    auto s = f.stats("ch");
    CHECK(s.drops == 0);
    CHECK(s.rows_sampled == 64);
    CHECK(f.driver->reads == 64);
    f.engine->run_upload_once(true);  // room again
    f.clock->advance(1ms);
    f.engine->run_sampling_once();  // ticks 64..69 missed (null), tick 70 read
    f.engine->run_upload_once(true);
    s = f.stats("ch");
    CHECK(s.drops == 0);
    CHECK(s.overruns == 6);
    const auto cols = f.columns("Sample/dev1/ch");
    REQUIRE(cols[0].size() == 71);  // every tick has its row
    CHECK(cols[0][63] == 64);
    CHECK(cols[0][64].is_null());
    CHECK(cols[0][70] == 65);
}

TEST_CASE("one sampling thread serves every channel") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("a", {"a"}, 1, 10)).ok());
    REQUIRE(f.engine->add_channel(EngineFixture::spec("b", {"b"}, 2, 10)).ok());
    REQUIRE(f.engine->add_channel(EngineFixture::spec("c", {"c"}, 5, 10)).ok());
    f.engine->start();
    REQUIRE(f.sleeper->wait_idle(2));
    for (int i = 0; i < 20; ++i) {
        f.sleeper->advance(1ms);
        REQUIRE(f.sleeper->wait_idle(2));
    }
    f.engine->stop();
    CHECK(f.stats("a").rows_sampled == 21);
    CHECK(f.stats("b").rows_sampled == 11);
    CHECK(f.stats("c").rows_sampled == 5);
    CHECK(f.stats("a").overruns == 0);
    std::lock_guard<std::mutex> lock(f.driver->mutex);
    CHECK(f.driver->threads.size() == 1);  // direct reads: all on the one sampling thread
    CHECK(f.driver->threads.count(std::this_thread::get_id()) == 0);
    // stop() published everything that was sampled
    CHECK(f.stats("a").rows_published == 21);
}

TEST_CASE("worker reads (direct_reads off) still give every row") {
    SamplingConfig config;
    config.direct_reads = false;
    EngineFixture f(config);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("a", {"a", "b"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 50ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/a");
    CHECK(cols[0] == std::vector<Json>{1, 2, 3, 4, 5, 6});
}

TEST_CASE("channels are added and removed while running and removal publishes what was sampled") {
    EngineFixture f;
    f.engine->start();
    REQUIRE(f.engine->add_channel(EngineFixture::spec("a", {"a"}, 10, 1000)).ok());
    CHECK(f.engine->add_channel(EngineFixture::spec("a", {"b"}, 10, 1000)).error().code == ErrorCode::key_error);
    f.sleeper->wake();
    REQUIRE(f.sleeper->wait_idle(2));
    for (int i = 0; i < 5; ++i) {
        f.sleeper->advance(10ms);
        REQUIRE(f.sleeper->wait_idle(2));
    }
    REQUIRE(f.stats("a").rows_sampled == 6);
    CHECK(f.dtus("Sample/dev1/a").empty());  // the upload period is 1 s
    REQUIRE(f.engine->remove_channel("a"));
    CHECK_FALSE(f.engine->remove_channel("a"));
    CHECK_FALSE(f.engine->has_channel("a"));
    f.sleeper->wake();
    REQUIRE(eventually([&] { return f.engine->stats().empty(); }));
    const auto cols = f.columns("Sample/dev1/a");
    REQUIRE(cols.size() == 1);
    CHECK(cols[0].size() == 6);
    // the id is free again
    CHECK(f.engine->add_channel(EngineFixture::spec("a", {"b"}, 10, 1000)).ok());
}

TEST_CASE("add_channel refuses bad specs") {
    EngineFixture f;
    CHECK(f.engine->add_channel(EngineFixture::spec("", {"a"}, 10, 100)).error().code == ErrorCode::parameter_missing);
    CHECK(f.engine->add_channel(EngineFixture::spec("x", {}, 10, 100)).error().code == ErrorCode::syntax_error);
    CHECK(f.engine->add_channel(EngineFixture::spec("x", {"a"}, 0, 100)).error().code == ErrorCode::unsupported_get_length);
    CHECK(f.engine->add_channel(EngineFixture::spec("x", {"a"}, 100, 10)).error().code == ErrorCode::unsupported_get_length);
    CHECK(f.engine->add_channel(EngineFixture::spec("x", {"a"}, -1, 10)).error().code == ErrorCode::unsupported_get_length);
    CHECK(f.engine->stats().empty());
}

TEST_CASE("text values survive until published and the tap sees every drained row") {
    EngineFixture f;
    f.driver->texts["st"] = "running";
    std::vector<std::pair<std::string, std::int64_t>> seen;
    f.tap.add([&](const std::vector<std::string>& ids, const SampleValue* values, std::int64_t time_ms) {
        REQUIRE(ids == std::vector<std::string>{"a", "st"});
        seen.emplace_back(std::string(values[1].as_text()), time_ms);
    });
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a", "st"}, 10, 100)).ok());
    CHECK(f.tap.sampled("st"));
    CHECK_FALSE(f.tap.sampled("zz"));
    f.engine->run_sampling_once();
    f.step(10ms, 10ms);
    {
        std::lock_guard<std::mutex> lock(f.driver->mutex);
        f.driver->texts["st"] = "idle";
    }
    f.step(10ms, 10ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    CHECK(cols[1] == std::vector<Json>{"running", "running", "idle"});
    REQUIRE(seen.size() == 3);
    CHECK(seen[2].first == "idle");
    CHECK(seen[1].second == 1'700'000'000'010);
    f.engine->remove_channel("ch");
    CHECK_FALSE(f.tap.sampled("st"));
}

TEST_CASE("SDK-held items are read from the value store and not from the driver") {
    EngineFixture f;
    auto state = std::make_shared<feature_detail::ModelState>();
    state->store = std::make_shared<ValueStore>();
    REQUIRE(state->store->add("fixed", DataKind::single, false, Json(42)).ok());
    f.engine->set_model(state);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a", "fixed"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 10ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    CHECK(cols[0] == std::vector<Json>{1, 2});
    CHECK(cols[1] == std::vector<Json>{42, 42});
    std::lock_guard<std::mutex> lock(f.driver->mutex);
    CHECK(f.driver->counters.count("fixed") == 0);
}

TEST_CASE("statistics count rows and DTUs and lateness") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 10, 20)).ok());
    f.engine->run_sampling_once();
    f.clock->advance(10ms + 150us);
    f.engine->run_sampling_once();
    f.engine->run_upload_once(true);
    const auto s = f.stats("ch");
    CHECK(s.points == 1);
    CHECK(s.rows_sampled == 2);
    CHECK(s.rows_published == 2);
    CHECK(s.dtus_published == 1);
    CHECK(s.lateness[0] == 1);  // tick 0: on time
    CHECK(s.lateness[4] == 1);  // 150 us: [100, 200)
    CHECK(s.max_lateness_us == 150);
    CHECK(s.topic == "Sample/dev1/ch");
}

TEST_CASE("a channel added while the uploader retires a removed one still gets published") {
    // A Probe/Set replaces ch1 by ch2; the add can land while the uploader
    // is publishing ch1's last rows. Here the sink itself adds ch2 then.
    EngineFixture f;
    std::vector<Message> sent;
    bool added = false;
    sampling_detail::EngineDeps deps;
    deps.driver = f.runner.get();
    deps.clock = f.clock;
    deps.sleeper = f.sleeper;
    deps.dev = "dev1";
    sampling_detail::SamplingEngine* engine_ptr = nullptr;
    deps.sink = [&](Message m) {
        if (!added && m.topic == "Sample/dev1/ch1") {
            added = true;
            REQUIRE(engine_ptr->add_channel(EngineFixture::spec("ch2", {"b"}, 10, 20)).ok());
        }
        sent.push_back(std::move(m));
    };
    sampling_detail::SamplingEngine engine(std::move(deps));
    engine_ptr = &engine;
    REQUIRE(engine.add_channel(EngineFixture::spec("ch1", {"a"}, 10, 100)).ok());
    engine.run_sampling_once();
    engine.run_upload_once();  // the uploader knows ch1
    REQUIRE(engine.remove_channel("ch1"));
    engine.run_upload_once();  // publishes ch1's last row (the sink adds ch2) and retires ch1
    REQUIRE(added);
    for (int i = 0; i < 5; ++i) {
        f.clock->advance(10ms);
        engine.run_sampling_once();
        engine.run_upload_once();
    }
    const auto ch2 = std::count_if(sent.begin(), sent.end(), [](const Message& m) { return m.topic == "Sample/dev1/ch2"; });
    CHECK(ch2 >= 2);
}

TEST_CASE("a ring larger than the address space is refused with its channel, not wrapped") {
    // A quarter of size_t in rows of 6 values: 24 GiB on a 32-bit target
    // (armhf), exabytes on a 64-bit one. Before, the array size wrapped (a
    // small allocation written as a large one) or the power-of-two rounding
    // never ended.
    SamplingConfig config;
    config.ring_max_rows = std::numeric_limits<std::size_t>::max() / 4;
    EngineFixture f(config);
    // 4 upload periods of 1e12 rows each: capped at ring_max_rows.
    const auto r = f.engine->add_channel(EngineFixture::spec("huge", {"a", "b", "c", "d", "e", "f"}, 1, 1e12));
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::out_of_range);
    CHECK_THAT(r.error().message, Catch::Contains("sample channel huge") && Catch::Contains("does not fit in memory"));
    // The engine keeps serving: an ordinary channel still gets in and samples.
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ok", {"a"}, 1, 10)).ok());
    f.engine->run_sampling_once();
    CHECK(f.stats("ok").rows_sampled == 1);
}

TEST_CASE("ring sizes: rounding saturates at the top bit and a size past size_t is 0") {
    using sampling_detail::ring_bytes;
    using sampling_detail::round_up_pow2;
    constexpr std::size_t top = ~(~std::size_t{0} >> 1);
    CHECK(round_up_pow2(64) == 64);
    CHECK(round_up_pow2(65) == 128);
    CHECK(round_up_pow2(top) == top);
    CHECK(round_up_pow2(top + 1) == top);  // was an endless loop
    CHECK(ring_bytes(64, 6) == 64 * (6 * sizeof(SampleValue) + 16));
    CHECK(ring_bytes(top + 1, 1) == 0);
    CHECK(ring_bytes(top / 16, 6) == 0);
    CHECK(ring_bytes(64, std::numeric_limits<std::size_t>::max() / 8) == 0);
}

TEST_CASE("a ring holds its upload periods and a floor in time, not a floor in rows") {
    // One row per upload period, sampled once a second: ring_periods 4 asks
    // for 4 rows; the time floor (250 ms) asks for less. Before, 64 rows.
    {
        EngineFixture f(SamplingConfig{});
        std::vector<std::string> points;
        for (int i = 0; i < 300; ++i) points.push_back("p" + std::to_string(i));
        REQUIRE(f.engine->add_channel(EngineFixture::spec("slow", points, 1000, 1000)).ok());
        CHECK(f.stats("slow").ring_capacity == 4);
    }
    // A 1 ms channel uploaded every 10 ms needs 40 rows for its periods; the
    // 250 ms floor gives it 250, rounded up to 256 (before, 64: 64 ms).
    {
        EngineFixture f(SamplingConfig{});
        REQUIRE(f.engine->add_channel(EngineFixture::spec("fast", {"a"}, 1, 10)).ok());
        CHECK(f.stats("fast").ring_capacity == 256);
    }
    // Without a time floor the periods decide (40 -> 64), and never fewer
    // than 4 rows; ring_max_rows caps the floor as it caps the periods.
    {
        SamplingConfig config;
        config.ring_min_ms = 0;
        EngineFixture f(config);
        REQUIRE(f.engine->add_channel(EngineFixture::spec("fast", {"a"}, 1, 10)).ok());
        REQUIRE(f.engine->add_channel(EngineFixture::spec("once", {"a"}, 1000, 1000)).ok());
        CHECK(f.stats("fast").ring_capacity == 64);
        CHECK(f.stats("once").ring_capacity == 4);
    }
    {
        SamplingConfig config;
        config.ring_max_rows = 16;
        EngineFixture f(config);
        REQUIRE(f.engine->add_channel(EngineFixture::spec("fast", {"a"}, 1, 10)).ok());
        CHECK(f.stats("fast").ring_capacity == 16);
    }
}
