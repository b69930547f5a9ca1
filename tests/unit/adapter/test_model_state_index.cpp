// ModelState::entry(): one lookup for what a request needs of an item (the
// data object, its binding, its chapter-7 rule), the same answers as the
// three lookups it replaces, before and after the binding is indexed.
#include "adapter/model_host.hpp"
#include "driver/driver_runner.hpp"
#include "support/adapter_fixture.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::adapter_detail;
using namespace nclink::driver_detail;
using namespace nclink::feature_detail;

TEST_CASE("ModelState::entry answers as item(), bound() and the rule lookup, indexed or not") {
    const Logger logger(stderr_sink(), LogLevel::warn);
    auto driver = std::make_shared<nclink::test::FakeDriver>();
    DriverRunner runner{driver, DriverRunner::Options{}, logger};
    ModelHost host{"", logger};
    auto built = host.build(load_model_file(nclink::test::test_model_path()), "", *driver);
    REQUIRE(built.ok());
    ModelState& state = *built.value();

    std::vector<std::string> ids{"no-such-item", ""};
    for (const auto& object : state.model->data_objects()) ids.push_back(object.id);
    for (const auto& method : state.model->methods()) ids.push_back(method.id);  // not data items
    const auto same_as_lookups = [&] {
        for (const auto& id : ids) {
            INFO(id);
            const auto entry = state.entry(id);
            CHECK(entry.object == state.item(id));
            CHECK(entry.bound == (entry.object ? state.bound(id) : nullptr));
            CHECK(entry.rule == (entry.object ? state.rules->find(id) : nullptr));
        }
    };
    SECTION("without a binding: the three lookups") { same_as_lookups(); }
    SECTION("bound and indexed") {
        REQUIRE(ModelHost::bind(state, runner).ok());
        same_as_lookups();
        // The driver's items are in the binding, the SDK-held ones are not.
        const auto pos = state.entry("pos");
        REQUIRE(pos.object != nullptr);
        CHECK(pos.bound != nullptr);
        CHECK_FALSE(state.sdk_held("pos"));
        std::size_t held = 0;
        for (const auto& object : state.model->data_objects())
            if (state.sdk_held(object.id)) {
                ++held;
                CHECK(state.entry(object.id).bound == nullptr);
            }
        CHECK(held > 0);
    }
}
