#include <nclink/driver_plugin_loader.hpp>

#include <catch2/catch.hpp>

#include <mutex>
#include <string>
#include <vector>

using namespace nclink;

namespace {

std::string plugin(const char* name) { return std::string(NCLINK_TEST_PLUGIN_DIR) + "/" + name + ".so"; }

class NoopControl final : public MethodControl {
public:
    std::vector<double> seen;
    void progress(double p) override { seen.push_back(p); }
    bool cancelled() const override { return false; }
    bool checkpoint() override { return true; }
};

}  // namespace

TEST_CASE("a plain C plugin loads and serves reads, writes and methods") {
    std::vector<std::string> logs;
    std::mutex mutex;
    Logger logger([&](LogLevel, std::string_view m) {
        std::lock_guard<std::mutex> lock(mutex);
        logs.emplace_back(m);
    }, LogLevel::trace);
    auto loaded = load_driver_plugin(plugin("c_counter"), Json{{"machine", "mill-1"}}, logger);
    REQUIRE(loaded.ok());
    auto driver = loaded.value();
    CHECK(driver->info().name == "c-counter");
    CHECK(driver->info().version == "1.2.3");
    CHECK_FALSE(driver->info().concurrent);
    REQUIRE(logs.size() == 1);
    CHECK(logs[0] == R"({"machine":"mill-1"})");  // the plugin saw its config

    std::vector<PointRef> points{{"a", DataKind::single}, {"fail", DataKind::single}, {"silent", DataKind::list}, {"b", DataKind::single}};
    std::vector<Result<Json>> results(points.size(), Result<Json>(make_error(ErrorCode::unavailable)));
    driver->read(points, results);
    REQUIRE(results[0].ok());
    CHECK(results[0].value() == 1);
    REQUIRE_FALSE(results[1].ok());
    CHECK(results[1].error().code == ErrorCode::unavailable);
    CHECK(results[1].error().message == "sensor disconnected");
    REQUIRE_FALSE(results[2].ok());
    CHECK(results[2].error().message == "plugin gave no value");
    CHECK(results[3].value() == 2);

    WriteRequest w;
    w.id = "x";
    w.params = Json{{"value", 5}};
    w.new_value = 5;
    CHECK(driver->write(w).ok());
    w.id = "ro";
    auto refused = driver->write(w);
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::permission_denied);
    CHECK(refused.error().message == "ro is wired read-only");

    CHECK(driver->claims("tool_table"));
    CHECK_FALSE(driver->claims("x"));

    NoopControl control;
    auto ret = driver->call_method("count", Json::object(), control);
    REQUIRE(ret.ok());
    CHECK(ret.value() == Json{{"counted", 3}});
    CHECK(control.seen == std::vector<double>{0, 50, 100});
    auto unknown = driver->call_method("nope", nullptr, control);
    REQUIRE_FALSE(unknown.ok());
    CHECK(unknown.error().code == ErrorCode::node_not_exists);
}

TEST_CASE("method control crosses the C ABI: a cancelled checkpoint ends the method early") {
    auto loaded = load_driver_plugin(plugin("c_counter"));
    REQUIRE(loaded.ok());
    struct CancelAt50 final : MethodControl {
        std::vector<double> seen;
        void progress(double p) override { seen.push_back(p); }
        bool cancelled() const override { return !seen.empty() && seen.back() >= 50; }
        bool checkpoint() override { return !cancelled(); }
    } control;
    auto ret = loaded.value()->call_method("count", Json::object(), control);
    REQUIRE(ret.ok());
    CHECK(ret.value().is_null());  // cancelled before it put a return value
    CHECK(control.seen == std::vector<double>{0, 50});
}

TEST_CASE("a driver without methods answers 202 to call_method") {
    struct Bare final : Driver {
        void read(const std::vector<PointRef>&, std::vector<Result<Json>>&) override {}
    } bare;
    NoopControl control;
    auto r = bare.call_method("any", nullptr, control);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::unavailable);
}

TEST_CASE("a C++ driver exported with NCLINK_EXPORT_DRIVER loads through the same ABI") {
    auto loaded = load_driver_plugin(plugin("cpp_exported"), Json{{"prefix", "x="}});
    REQUIRE(loaded.ok());
    auto driver = loaded.value();
    CHECK(driver->info().name == "cpp-echo");
    CHECK(driver->info().concurrent);
    CHECK_FALSE(driver->claims("p1"));  // passed through the ABI: EchoDriver claims nothing
    std::vector<PointRef> points{{"p1", DataKind::single}, {"tools", DataKind::list}};
    std::vector<Result<Json>> results(2, Result<Json>(make_error(ErrorCode::unavailable)));
    driver->read(points, results);
    CHECK(results[0].value() == "x=p1");
    CHECK(results[1].value() == Json::array({1, 2, 3}));
    WriteRequest w;
    w.id = "p1";
    w.new_value = "text";
    auto bad = driver->write(w);
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::value_type);
    NoopControl control;
    auto ret = driver->call_method("m1", Json{{"a", 1}}, control);
    REQUIRE(ret.ok());
    CHECK(ret.value()["args"]["a"] == 1);

    auto refused = load_driver_plugin(plugin("cpp_exported"), Json{{"refuse", true}});
    REQUIRE_FALSE(refused.ok());
    CHECK_THAT(refused.error().message, Catch::Contains("told to refuse"));
}

TEST_CASE("broken plugins are refused with a clear message") {
    SECTION("wrong ABI version") {
        auto r = load_driver_plugin(plugin("wrong_abi"));
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().code == ErrorCode::value_type);
        CHECK_THAT(r.error().message, Catch::Contains("ABI version 999 is not supported"));
    }
    SECTION("no entry symbol") {
        auto r = load_driver_plugin(plugin("no_entry"));
        REQUIRE_FALSE(r.ok());
        CHECK_THAT(r.error().message, Catch::Contains("no 'nclink_driver_entry' symbol"));
    }
    SECTION("a required function missing") {
        auto r = load_driver_plugin(plugin("missing_read"));
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().code == ErrorCode::parameter_missing);
        CHECK_THAT(r.error().message, Catch::Contains("lacks required function(s): read"));
    }
    SECTION("create refuses") {
        auto r = load_driver_plugin(plugin("refusing"));
        REQUIRE_FALSE(r.ok());
        CHECK_THAT(r.error().message, Catch::Contains("refused to start: no CNC at 192.0.2.7"));
    }
    SECTION("no such file") {
        auto r = load_driver_plugin("/nonexistent/driver.so");
        REQUIRE_FALSE(r.ok());
        CHECK_THAT(r.error().message, Catch::Contains("cannot load driver plugin /nonexistent/driver.so"));
    }
}
