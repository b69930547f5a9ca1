// Sampled values against chapter 7: a value breaking its item's rule goes out
// as null, counted per channel and by the guard; good values pass untouched.
#include "engine_fixture.hpp"

#include "feature/value_guard.hpp"

#include <nclink/model.hpp>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

std::shared_ptr<const feature_detail::ModelState> state_of(const std::string& text) {
    const LoadResult loaded = parse_model(text);
    REQUIRE(loaded.ok());
    auto state = std::make_shared<feature_detail::ModelState>();
    state->model = loaded.model;
    state->device = &loaded.model->devices().front();
    state->rules = std::make_shared<const ValueRules>(*loaded.model);
    return state;
}

/// A model of one MACHINE (guid dev1) whose data items are `items` (JSON).
std::shared_ptr<const feature_detail::ModelState> machine_with(const std::string& items) {
    return state_of(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[{"id":"d","type":"MACHINE",
      "guid":"dev1","version":"1.0.0","dataItems":)" +
                    items + "}]}");
}

/// Channel "c" of `ids` at 10 ms / 100 ms: one upload period sampled and published.
void sample_one_period(EngineFixture& f, const std::vector<std::string>& ids) {
    REQUIRE(f.engine->add_channel(EngineFixture::spec("c", ids, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 90ms);
    f.engine->run_upload_once(true);
}

}  // namespace

TEST_CASE("sampled values breaking chapter 7 are sent as null and counted") {
    auto state = machine_with(R"([{"id":"mode","type":"SPINDLE_MODE"},{"id":"n","type":"POSITION"},{"id":"w","type":"WARNING"}])");
    feature_detail::ValueGuard guard{Logger{}};
    EngineFixture f({}, false, nullptr, state, &guard);
    f.driver->texts["mode"] = "spinning";  // not a value of table 15
    f.driver->texts["w"] = "text";         // a WARNING is an object
    sample_one_period(f, {"mode", "n", "w"});
    const auto cols = f.columns("Sample/dev1/c");
    REQUIRE(cols.size() == 3);
    for (const auto& v : cols[0]) CHECK(v.is_null());
    for (const auto& v : cols[1]) CHECK(v.is_number());  // a POSITION number passes
    for (const auto& v : cols[2]) CHECK(v.is_null());
    CHECK(f.stats("c").refused_values == 2 * cols[0].size());
    CHECK(guard.refused() == 2 * cols[0].size());
    CHECK(guard.refused_items() == 2);

    // A good text passes.
    f.driver->texts["mode"] = "forward";
    f.step(10ms, 100ms);
    f.engine->run_upload_once(true);
    const auto later = f.columns("Sample/dev1/c");
    CHECK(later[0].back() == "forward");
}

TEST_CASE("sampled doubles outside a number item's range are sent as null, those inside pass") {
    // MASS is never negative, POWER_FACTOR at most 1 (table 10); the
    // uploader checks float64 samples of such items inline.
    auto state = machine_with(R"([{"id":"m","type":"MASS"},{"id":"pf","type":"POWER_FACTOR"},{"id":"n","type":"POSITION"}])");
    feature_detail::ValueGuard guard{Logger{}};
    EngineFixture f({}, false, nullptr, state, &guard);
    f.driver->doubles["m"] = -1.5;
    f.driver->doubles["pf"] = 0.75;
    f.driver->doubles["n"] = -1e300;
    sample_one_period(f, {"m", "pf", "n"});
    const auto cols = f.columns("Sample/dev1/c");
    REQUIRE(cols.size() == 3);
    REQUIRE(!cols[0].empty());
    for (const auto& v : cols[0]) CHECK(v.is_null());
    for (const auto& v : cols[1]) CHECK(v == 0.75);
    for (const auto& v : cols[2]) CHECK(v == -1e300);  // a position has no bound
    CHECK(f.stats("c").refused_values == cols[0].size());
    CHECK(guard.refused_items() == 1);

    // Back in range: passes; the bound is inclusive (1.0 is a power factor).
    f.driver->doubles["m"] = 0.0;
    f.driver->doubles["pf"] = 1.0;
    f.step(10ms, 100ms);
    f.engine->run_upload_once(true);
    const auto later = f.columns("Sample/dev1/c");
    CHECK(later[0].back() == 0.0);
    CHECK(later[1].back() == 1.0);
    f.driver->doubles["pf"] = 1.0000001;
    f.step(10ms, 100ms);
    f.engine->run_upload_once(true);
    CHECK(f.columns("Sample/dev1/c")[1].back().is_null());
}

TEST_CASE("a double where an item takes text, or text where it takes a number, is refused, items without a rule pass") {
    // The inline range test only ever passes a double inside a number
    // item's bounds; everything else meets its item's full rule.
    auto state = machine_with(R"([{"id":"mode","type":"SPINDLE_MODE"},{"id":"m","type":"MASS"}])");
    feature_detail::ValueGuard guard{Logger{}};
    EngineFixture f({}, false, nullptr, state, &guard);
    f.driver->doubles["mode"] = 2.0;    // table 15 takes a text
    f.driver->texts["m"] = "heavy";     // table 10 takes a number
    f.driver->doubles["free"] = -7.25;  // not in the model: no rule
    sample_one_period(f, {"mode", "m", "free"});
    const auto cols = f.columns("Sample/dev1/c");
    REQUIRE(cols.size() == 3);
    REQUIRE(!cols[0].empty());
    for (const auto& v : cols[0]) CHECK(v.is_null());
    for (const auto& v : cols[1]) CHECK(v.is_null());
    for (const auto& v : cols[2]) CHECK(v == -7.25);
    CHECK(f.stats("c").refused_values == 2 * cols[0].size());
    CHECK(guard.refused_items() == 2);
}
