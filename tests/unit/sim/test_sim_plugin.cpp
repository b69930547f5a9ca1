// nclink-sim.so loads through the plugin ABI and serves the model it is given.
#include <nclink/driver_plugin_loader.hpp>
#include <nclink/sample_value.hpp>

#include <catch2/catch.hpp>

#include <string>

using namespace nclink;

namespace {

std::string plugin_path() { return std::string(NCLINK_BINARY_DIR) + "/lib/nclink-sim.so"; }
std::string model_path(const char* file) { return std::string(NCLINK_MODELS_DIR) + "/" + file; }

struct Control final : MethodControl {
    double last = 0;
    void progress(double p) override { last = p; }
    bool cancelled() const override { return false; }
    bool checkpoint() override { return true; }
};

}  // namespace

TEST_CASE("the plugin simulates the mill from its configuration") {
    auto loaded = load_driver_plugin(plugin_path(), Json{{"model", model_path("sim-mill.json")}, {"seed", 3}});
    REQUIRE(loaded.ok());
    auto driver = loaded.value();
    CHECK(driver->info().name == "nclink-sim");

    std::vector<PointRef> points{{"x_position", DataKind::single},
                                 {"status", DataKind::single},
                                 {"tools", DataKind::list},
                                 {"parameters", DataKind::dict},
                                 {"nope", DataKind::single}};
    std::vector<Result<Json>> results(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    driver->read(points, results);
    REQUIRE(results[0].ok());
    CHECK(results[0].value().is_number());
    CHECK(results[1].value() == "running");
    CHECK(results[2].value().size() == 64);
    CHECK(results[3].value().is_object());
    REQUIRE_FALSE(results[4].ok());
    CHECK(results[4].error().code == ErrorCode::node_not_exists);

    WriteRequest w;
    w.id = "feed_override";
    w.params = Json{{"value", 50}};
    CHECK(driver->write(w).ok());
    Control control;
    auto held = driver->run_method(PointRef{"feed_hold"}, Json::object(), control);
    REQUIRE(held.ok());
    CHECK(held.value()["status"] == "holding");
    CHECK(control.last == 100);
}

TEST_CASE("the plugin simulates a deviating model") {
    auto loaded = load_driver_plugin(plugin_path(), Json{{"model", model_path("appendix-b.json")}, {"list_size", 4}});
    REQUIRE(loaded.ok());
    std::vector<PointRef> points{{"0103080402", DataKind::single}, {"01031207", DataKind::list}};
    std::vector<Result<Json>> results(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    loaded.value()->read(points, results);
    CHECK(results[0].value().is_number());
    CHECK(results[1].value().size() == 4);
}

TEST_CASE("the plugin refuses a missing or broken model") {
    auto no_model = load_driver_plugin(plugin_path(), Json::object());
    REQUIRE_FALSE(no_model.ok());
    auto missing = load_driver_plugin(plugin_path(), Json{{"model", model_path("does-not-exist.json")}});
    REQUIRE_FALSE(missing.ok());
    CHECK(missing.error().message.find("does-not-exist.json") != std::string::npos);
    auto bad_seed = load_driver_plugin(plugin_path(), Json{{"model", model_path("sim-mill.json")}, {"seed", "x"}});
    REQUIRE_FALSE(bad_seed.ok());
}

TEST_CASE("the plugin binds handles and serves reads, typed samples and methods by them") {
    auto loaded = load_driver_plugin(plugin_path(), Json{{"model", model_path("sim-mill.json")}, {"seed", 3}});
    REQUIRE(loaded.ok());
    auto driver = loaded.value();
    std::vector<BindPoint> bind(4);
    bind[0].id = "x_position";
    bind[1].id = "status";
    bind[2].id = "nope";
    bind[3].id = "feed_hold";
    bind[3].method = true;
    std::vector<PointHandle> handles(bind.size(), no_handle);
    REQUIRE(driver->bind(bind, handles).ok());
    CHECK(handles[0] != no_handle);
    CHECK(handles[1] != no_handle);
    CHECK(handles[2] == no_handle);  // not simulated: left by id, read answers 401
    CHECK(handles[3] != no_handle);
    // The handle decides, not the id: the id is only the fallback.
    std::vector<PointRef> points{{"renamed", DataKind::single, handles[1]}, {"nope", DataKind::single, handles[2]}};
    std::vector<Result<Json>> results(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    driver->read(points, results);
    CHECK(results[0].value() == "running");
    CHECK(results[1].error().code == ErrorCode::node_not_exists);
    std::vector<SampleValue> row(points.size());
    REQUIRE(driver->read_samples(points, row.data()));  // typed through the ABI
    CHECK(row[0].kind() == SampleValue::Kind::text);
    CHECK(row[0].as_text() == "running");
    CHECK(row[1].kind() == SampleValue::Kind::null);
    Control control;
    auto held = driver->run_method(PointRef{"not-its-id", DataKind::single, handles[3]}, Json::object(), control);
    REQUIRE(held.ok());
    CHECK(held.value()["status"] == "holding");
    CHECK(driver->link().state == MachineLink::connected);
}
