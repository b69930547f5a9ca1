// Push mode: rows written by a firmware thread through PushChannel.
#include "engine_fixture.hpp"

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {
sampling_detail::ChannelSpec push_spec(const std::string& id, std::vector<std::string> ids, double sample_ms, double upload_ms) {
    auto s = EngineFixture::spec(id, std::move(ids), sample_ms, upload_ms);
    s.push = true;
    return s;
}
}  // namespace

TEST_CASE("pushed rows are published like sampled ones with the caller's timestamps") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(push_spec("servo", {"x", "y"}, 1, 10)).ok());
    auto handle = f.engine->push_channel("servo");
    REQUIRE(handle.ok());
    PushChannel ch = handle.value();
    CHECK(ch.points() == 2);
    CHECK(ch.id() == "servo");
    for (int i = 0; i < 10; ++i) {
        const SampleValue row[2] = {SampleValue::float64(i * 0.5), SampleValue::int64(i)};
        REQUIRE(ch.push(row, 2, (1'700'000'000'000 + i) * 1'000'000LL));
    }
    f.engine->run_sampling_once();  // the sampler never reads a push channel
    CHECK(f.driver->reads == 0);
    f.engine->run_upload_once(true);
    const auto dtus = f.dtus("Sample/dev1/servo");
    REQUIRE(dtus.size() == 1);
    CHECK(dtus[0].at("beginTime") == "1700000000000");
    CHECK(dtus[0].at("data")[0].at("data") == Json::array({0, 0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 4.5}));
    CHECK(dtus[0].at("data")[1].at("data") == Json::array({0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
    const auto s = f.stats("servo");
    CHECK(s.push);
    CHECK(s.rows_sampled == 10);
    CHECK(s.rows_published == 10);
}

TEST_CASE("push refuses a wrong column count and a removed channel and a stopped engine") {
    EngineFixture f;
    REQUIRE(f.engine->add_channel(push_spec("servo", {"x", "y"}, 1, 10)).ok());
    REQUIRE(f.engine->add_channel(EngineFixture::spec("pull", {"x"}, 1, 10)).ok());
    CHECK(f.engine->push_channel("pull").error().code == ErrorCode::value_type);
    CHECK(f.engine->push_channel("nope").error().code == ErrorCode::node_not_exists);
    PushChannel ch = f.engine->push_channel("servo").value();
    const SampleValue row[2] = {SampleValue::int64(1), SampleValue::int64(2)};
    CHECK_FALSE(ch.push(row, 1));
    CHECK(ch.push(row, 2));
    f.engine->start();
    f.engine->stop();
    CHECK_FALSE(ch.push(row, 2));  // stopped
    f.engine->start();
    CHECK(ch.push(row, 2));
    REQUIRE(f.engine->remove_channel("servo"));
    CHECK_FALSE(ch.push(row, 2));
    f.engine->stop();
    CHECK(f.columns("Sample/dev1/servo")[0].size() == 2);  // both accepted rows were published
    PushChannel empty;
    CHECK_FALSE(empty.push(row, 2));
    CHECK(empty.points() == 0);
}

TEST_CASE("a full push ring drops the oldest rows and the DTU restarts after the gap") {
    SamplingConfig config;
    config.ring_periods = 1;
    config.ring_min_ms = 64;  // 64 rows of 1 ms
    EngineFixture f(config);
    REQUIRE(f.engine->add_channel(push_spec("servo", {"x"}, 1, 10)).ok());
    PushChannel ch = f.engine->push_channel("servo").value();
    for (int i = 0; i < 100; ++i) {
        const SampleValue v = SampleValue::int64(i);
        REQUIRE(ch.push(&v, 1, (1'700'000'000'000LL + i) * 1'000'000));
    }
    CHECK(f.stats("servo").drops == 36);
    f.engine->run_upload_once(true);
    const auto dtus = f.dtus("Sample/dev1/servo");
    REQUIRE(dtus.size() == 4);  // 64 rows in DTUs of at most 2 upload periods (20 rows)
    CHECK(dtus[0].at("beginTime") == "1700000000036");
    CHECK(dtus[0].at("data")[0].at("data").front() == 36);
}

TEST_CASE("pushes from a thread while the engine runs all arrive in order") {
    SamplingConfig config;
    config.ring_periods = 1000;  // room for every row: this test is about order and integrity
    EngineFixture f(config);
    REQUIRE(f.engine->add_channel(push_spec("servo", {"x", "y", "z"}, 1, 10)).ok());
    PushChannel ch = f.engine->push_channel("servo").value();
    f.engine->start();
    std::thread firmware([&] {
        for (int i = 0; i < 3000; ++i) {
            const SampleValue row[3] = {SampleValue::int64(i), SampleValue::int64(i), SampleValue::int64(i)};
            REQUIRE(ch.push(row, 3));
            if (i % 100 == 0) f.sleeper->advance(5ms);  // the uploader drains and publishes on fake time
        }
    });
    firmware.join();
    f.engine->stop();
    CHECK(f.stats("servo").drops == 0);
    const auto cols = f.columns("Sample/dev1/servo");
    REQUIRE(cols.size() == 3);
    REQUIRE(cols[0].size() == 3000);
    for (std::size_t i = 0; i < 3000; ++i) {
        REQUIRE(cols[0][i] == static_cast<int>(i));
        REQUIRE(cols[2][i] == static_cast<int>(i));
    }
}
