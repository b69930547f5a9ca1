// Typed reads (Driver::read_samples), grid-aligned timelines and the DTU size
// cap: the pieces that keep the sampling cost near encoding + publishing.
#include "engine_fixture.hpp"

#include <nclink/adapter_config.hpp>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

/// Answers doubles for "x*" ids and the text of `status` for "st", through
/// read_samples(); counts read() calls, which should not come.
class TypedDriver : public Driver {
public:
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        ++json_reads;
        for (std::size_t i = 0; i < points.size(); ++i) results[i] = Json(-1);
    }
    bool read_samples(const std::vector<PointRef>& points, SampleValue* out) override {
        ++typed_reads;
        if (throw_next) {
            throw_next = false;
            out[0] = SampleValue::float64(99);  // half written, then fails
            throw std::runtime_error("bus error");
        }
        // One buffer rewritten at every call: the SDK must copy the text.
        text_buffer = status;
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (points[i].id == "st") out[i] = SampleValue::text(text_buffer);
            else if (points[i].id == "gone") continue;  // left null: not readable now
            else out[i] = SampleValue::float64(0.5 + typed_reads);
        }
        return true;
    }
    std::atomic<int> json_reads{0};
    int typed_reads = 0;
    bool throw_next = false;
    std::string status = "running";
    std::string text_buffer;
};

std::shared_ptr<const feature_detail::ModelState> store_with(const std::string& id, Json value) {
    auto state = std::make_shared<feature_detail::ModelState>();
    state->store = std::make_shared<ValueStore>();
    REQUIRE(state->store->add(id, DataKind::single, false, std::move(value)).ok());
    return state;
}

}  // namespace

TEST_CASE("a driver with read_samples is read typed and never through read()") {
    auto driver = std::make_shared<TypedDriver>();
    EngineFixture f({}, false, driver);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"x1", "x2", "gone"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 20ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    REQUIRE(cols.size() == 3);
    CHECK(cols[0] == std::vector<Json>{1.5, 2.5, 3.5});
    CHECK(cols[1] == cols[0]);
    CHECK(cols[2] == std::vector<Json>{nullptr, nullptr, nullptr});  // left null by the driver
    CHECK(f.stats("ch").null_values == 3);
    CHECK(driver->json_reads == 0);
}

TEST_CASE("borrowed text from read_samples is copied before the driver is called again") {
    auto driver = std::make_shared<TypedDriver>();
    EngineFixture f({}, false, driver);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"st"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    driver->status = "idle";
    f.step(10ms, 10ms);
    driver->status = "a status longer than any small-string buffer";
    f.step(10ms, 10ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    CHECK(cols[0] == std::vector<Json>{"running", "idle", "a status longer than any small-string buffer"});
}

TEST_CASE("a throwing read_samples gives a null row and sampling goes on") {
    auto driver = std::make_shared<TypedDriver>();
    EngineFixture f({}, false, driver);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"x1"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    driver->throw_next = true;
    f.step(10ms, 20ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    CHECK(cols[0] == std::vector<Json>{1.5, nullptr, 3.5});  // the half-written 99 is not sent
}

TEST_CASE("typed driver columns and SDK-held columns share a row in model order") {
    auto driver = std::make_shared<TypedDriver>();
    EngineFixture f({}, false, driver);
    f.engine->set_model(store_with("fixed", Json("ACME")));
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"fixed", "x1", "st"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 10ms);
    f.engine->run_upload_once(true);
    const auto cols = f.columns("Sample/dev1/ch");
    REQUIRE(cols.size() == 3);
    CHECK(cols[0] == std::vector<Json>{"ACME", "ACME"});
    CHECK(cols[1] == std::vector<Json>{1.5, 2.5});
    CHECK(cols[2] == std::vector<Json>{"running", "running"});
}

TEST_CASE("a driver without read_samples is read through read() and its Json converted") {
    EngineFixture f;  // CountingDriver implements read() only
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 10ms);
    f.engine->run_upload_once(true);
    CHECK(f.columns("Sample/dev1/ch")[0] == std::vector<Json>{1, 2});
    std::lock_guard<std::mutex> lock(f.driver->mutex);
    CHECK(f.driver->reads == 2);
}

TEST_CASE("a channel started off its interval's grid waits for the grid, so channels tick together") {
    EngineFixture f;
    f.clock->advance(3ms);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("a", {"a"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.clock->advance(4ms);  // t = 7 ms
    REQUIRE(f.engine->add_channel(EngineFixture::spec("b", {"b"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    CHECK(f.stats("a").rows_sampled == 0);
    CHECK(f.stats("b").rows_sampled == 0);
    f.clock->advance(3ms);  // t = 10 ms: both due in the same pass
    f.engine->run_sampling_once();
    CHECK(f.stats("a").rows_sampled == 1);
    CHECK(f.stats("b").rows_sampled == 1);
    CHECK(f.stats("a").lateness[0] == 1);  // on time: not late by the 3 ms it waited
    f.engine->run_upload_once(true);
    // Row times follow the grid too: 10 ms after the fake clock's start.
    CHECK(f.dtus("Sample/dev1/a").at(0).at("beginTime") == "1700000000010");
}

TEST_CASE("an engine's phase shifts its channels' grid by that fraction of the interval") {
    // Gateway mode gives each adapter its own phase (EngineDeps::phase), so
    // the machines of one process do not all sample at the same instant.
    EngineFixture f({}, false, nullptr, nullptr, nullptr, 0.25);
    f.clock->advance(3ms);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("a", {"a"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.clock->advance(9ms);  // t = 12 ms: the unshifted grid point (10 ms) has passed
    f.engine->run_sampling_once();
    CHECK(f.stats("a").rows_sampled == 0);
    f.clock->advance(500us);  // t = 12.5 ms = 10 ms + 0.25 x 10 ms
    f.engine->run_sampling_once();
    CHECK(f.stats("a").rows_sampled == 1);
    CHECK(f.stats("a").lateness[0] == 1);  // on time
    f.clock->advance(10ms);                // t = 22.5 ms: the next tick, one interval on
    f.engine->run_sampling_once();
    CHECK(f.stats("a").rows_sampled == 2);
}

TEST_CASE("a long-interval channel starts on the next whole second, not a whole interval later") {
    EngineFixture f;
    f.clock->advance(3ms);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("slow", {"a"}, 10000, 60000)).ok());
    f.engine->run_sampling_once();
    f.clock->advance(996ms);  // t = 999 ms
    f.engine->run_sampling_once();
    CHECK(f.stats("slow").rows_sampled == 0);
    f.clock->advance(1ms);  // t = 1 s
    f.engine->run_sampling_once();
    CHECK(f.stats("slow").rows_sampled == 1);
}

TEST_CASE("max_dtu_bytes splits an upload period into consecutive DTUs without losing a row") {
    SamplingConfig config;
    config.max_dtu_bytes = 300;
    EngineFixture f(config);
    REQUIRE(f.engine->add_channel(EngineFixture::spec("ch", {"a", "b", "c"}, 10, 200)).ok());
    f.engine->run_sampling_once();
    for (int round = 0; round < 2; ++round) {  // the second period uses the measured row size
        f.step(10ms, 200ms);
        f.engine->run_upload_once(true);
    }
    const auto dtus = f.dtus("Sample/dev1/ch");
    REQUIRE(dtus.size() > 2);
    std::int64_t expected_begin = 1'700'000'000'000;
    std::vector<Json> a_values;
    for (const auto& d : dtus) {
        CHECK(d.dump().size() <= 300 + 60);  // the size is judged from the previous DTU's rows
        CHECK(d.at("beginTime") == std::to_string(expected_begin));
        const auto& rows = d.at("data")[0].at("data");
        expected_begin += 10 * static_cast<std::int64_t>(rows.size());
        a_values.insert(a_values.end(), rows.begin(), rows.end());
    }
    REQUIRE(a_values.size() == 41);
    for (std::size_t i = 0; i < a_values.size(); ++i) CHECK(a_values[i] == static_cast<std::int64_t>(i + 1));
}
