// Sampled values against chapter 7: a value breaking its item's rule goes out
// as null, counted per channel and by the guard; good values pass untouched.
#include "engine_fixture.hpp"

#include "feature/value_guard.hpp"

#include <nclink/model.hpp>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

namespace {

std::shared_ptr<const detail::ModelState> state_of(const char* text) {
    const LoadResult loaded = parse_model(text);
    REQUIRE(loaded.ok());
    auto state = std::make_shared<detail::ModelState>();
    state->model = loaded.model;
    state->device = &loaded.model->devices().front();
    state->rules = std::make_shared<const ValueRules>(*loaded.model);
    return state;
}

}  // namespace

TEST_CASE("sampled values breaking chapter 7 are sent as null and counted") {
    auto state = state_of(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[{"id":"d","type":"MACHINE",
      "guid":"dev1","version":"1.0.0","dataItems":[{"id":"mode","type":"SPINDLE_MODE"},{"id":"n","type":"POSITION"},
      {"id":"w","type":"WARNING"}]}]})");
    detail::ValueGuard guard{Logger{}};
    EngineFixture f({}, false, nullptr, state, &guard);
    f.driver->texts["mode"] = "spinning";  // not a value of table 15
    f.driver->texts["w"] = "text";         // a WARNING is an object
    REQUIRE(f.engine->add_channel(EngineFixture::spec("c", {"mode", "n", "w"}, 10, 100)).ok());
    f.engine->run_sampling_once();
    f.step(10ms, 90ms);
    f.engine->run_upload_once(true);
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
