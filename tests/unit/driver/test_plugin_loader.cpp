#include <nclink/driver_plugin_loader.hpp>
#include <nclink/sample_value.hpp>

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

TEST_CASE("a plain C plugin of ABI version 2 binds, reads typed values, writes and runs methods") {
    std::vector<std::string> logs;
    std::mutex mutex;
    Logger logger(
        [&](LogLevel, std::string_view m) {
            std::lock_guard<std::mutex> lock(mutex);
            logs.emplace_back(m);
        },
        LogLevel::trace);
    auto loaded = load_driver_plugin(plugin("c_counter"), Json{{"machine", "mill-1"}}, logger);
    REQUIRE(loaded.ok());
    auto driver = loaded.value();
    CHECK(driver->info().name == "c-counter");
    CHECK(driver->info().version == "1.2.3");
    CHECK_FALSE(driver->info().concurrent);
    REQUIRE(logs.size() == 1);
    CHECK(logs[0] == R"({"machine":"mill-1"})");  // the plugin saw its config

    // bind: the plugin's own numbers, not_served passed through.
    std::vector<BindPoint> bind_points(4);
    bind_points[0].id = "a";
    bind_points[1].id = "handle";
    bind_points[2].id = "hidden";
    bind_points[3].id = "count";
    bind_points[3].method = true;
    std::vector<PointHandle> handles(4, no_handle);
    REQUIRE(driver->bind(bind_points, handles).ok());
    CHECK(handles[0] == 0);  // the counter's row
    CHECK(handles[1] == 5);
    CHECK(handles[2] == not_served);
    CHECK(handles[3] == 10);
    CHECK(logs.back() == "bound 4 point(s)");

    std::vector<PointRef> points{{"a", DataKind::single, handles[0]},
                                 {"fail", DataKind::single},
                                 {"silent", DataKind::list},
                                 {"b", DataKind::single},
                                 {"name", DataKind::single},
                                 {"flag", DataKind::single},
                                 {"temp", DataKind::single},
                                 {"tools", DataKind::list},
                                 {"handle", DataKind::single, handles[1]},
                                 {"vendor", DataKind::single}};
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
    CHECK(results[4].value() == "say \"hi\"\n");
    CHECK(results[5].value() == true);
    CHECK(results[6].value() == 21.5);
    CHECK(results[7].value() == Json::parse(R"([{"id":1,"name":"drill \"8mm\"","length":50.25,"worn":false},
                                                {"id":2,"name":"mill\\tap","length":100.5,"worn":true}])"));
    CHECK(results[8].value() == 5);  // read with the handle bind gave
    REQUIRE_FALSE(results[9].ok());
    CHECK(static_cast<int>(results[9].error().code) == -7);  // the vendor's own code survives
    CHECK(results[9].error().message == "spindle drive fault E7");

    // The typed sampling read: no JSON for simple values, texts lent.
    std::vector<SampleValue> row(points.size());
    REQUIRE(driver->read_samples(points, row.data()));
    CHECK(row[0].kind() == SampleValue::Kind::int64);
    CHECK(row[1].kind() == SampleValue::Kind::null);  // failures are null in samples
    CHECK(row[4].kind() == SampleValue::Kind::text);
    CHECK(row[4].as_text() == "say \"hi\"\n");
    CHECK(row[5].as_bool());
    CHECK(row[6].as_double() == 21.5);
    CHECK(row[7].kind() == SampleValue::Kind::json);
    CHECK(Json::parse(row[7].as_text()).size() == 2);
    CHECK(row[8].kind() == SampleValue::Kind::uint64);
    CHECK(row[8].as_uint64() == 5);

    WriteRequest w;
    w.id = "x";
    w.params = Json{{"value", 5}};
    w.new_value = 5;
    CHECK(driver->write(w).ok());
    w.new_value = "five";
    auto typed = driver->write(w);
    REQUIRE_FALSE(typed.ok());
    CHECK(typed.error().code == ErrorCode::value_type);
    CHECK(typed.error().message == "an integer is expected");
    w.id = "ro";
    auto refused = driver->write(w);
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::permission_denied);
    CHECK(refused.error().message == "ro is wired read-only");
    w.id = "vendor";
    auto clamp = driver->write(w);
    REQUIRE_FALSE(clamp.ok());
    CHECK(static_cast<int>(clamp.error().code) == -12);
    CHECK(clamp.error().message == "axis clamp engaged");

    CHECK(driver->claims("tool_table"));
    CHECK_FALSE(driver->claims("x"));
    CHECK(driver->link().state == MachineLink::connected);

    NoopControl control;
    auto ret = driver->run_method(PointRef{"count", DataKind::single, handles[3]}, Json::object(), control);
    REQUIRE(ret.ok());
    CHECK(ret.value() == Json{{"counted", 3}});
    CHECK(control.seen == std::vector<double>{0, 50, 100});
    auto unknown = driver->run_method(PointRef{"nope"}, nullptr, control);
    REQUIRE_FALSE(unknown.ok());
    CHECK(unknown.error().code == ErrorCode::node_not_exists);
    CHECK(unknown.error().message == "no such method");
}

TEST_CASE("a C plugin's link and its configuration checks cross the ABI") {
    auto down = load_driver_plugin(plugin("c_counter"), Json{{"link_down", true}});
    REQUIRE(down.ok());
    const MachineLinkStatus link = down.value()->link();
    CHECK(link.state == MachineLink::disconnected);
    CHECK(link.reason == "CNC cable unplugged");
    auto bad = load_driver_plugin(plugin("c_counter"), Json{{"link_down", "yes"}});
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::value_type);  // create()'s code
    CHECK_THAT(bad.error().message, Catch::Contains("refused to start: link_down must be true or false"));
}

TEST_CASE("a version-2 descriptor shorter than this header's is read only as far as its struct_size") {
    auto loaded = load_driver_plugin(plugin("short_v2"));
    REQUIRE(loaded.ok());
    CHECK(loaded.value()->link().state == MachineLink::unknown);  // the field past struct_size is not called
    std::vector<PointRef> points{{"a", DataKind::single}};
    std::vector<Result<Json>> results(1, Result<Json>(make_error(ErrorCode::unavailable)));
    loaded.value()->read(points, results);
    CHECK(results[0].value() == 42);
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
    auto ret = loaded.value()->run_method(PointRef{"count"}, Json::object(), control);
    REQUIRE(ret.ok());
    CHECK(ret.value().is_null());  // cancelled before it put a return value
    CHECK(control.seen == std::vector<double>{0, 50});
}

TEST_CASE("a driver without methods answers 202 to run_method") {
    struct Bare final : Driver {
        void read(const std::vector<PointRef>&, std::vector<Result<Json>>&) override {}
    } bare;
    NoopControl control;
    auto r = bare.run_method(PointRef{"any"}, nullptr, control);
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
    // bind, handles, vendor codes and link cross the ABI as well.
    std::vector<BindPoint> bind_points(2);
    bind_points[0].id = "p1";
    bind_points[1].id = "h";
    std::vector<PointHandle> handles(2, no_handle);
    REQUIRE(driver->bind(bind_points, handles).ok());
    CHECK(handles == std::vector<PointHandle>{no_handle, 7});
    std::vector<PointRef> more{{"h", DataKind::single, handles[1]}, {"vendor", DataKind::single}};
    std::vector<Result<Json>> more_results(2, Result<Json>(make_error(ErrorCode::unavailable)));
    driver->read(more, more_results);
    CHECK(more_results[0].value() == 7);
    CHECK(static_cast<int>(more_results[1].error().code) == -3);
    CHECK(more_results[1].error().message == "coolant low");
    std::vector<SampleValue> row(2);
    REQUIRE(driver->read_samples(more, row.data()));
    CHECK(row[0].kind() == SampleValue::Kind::uint64);
    CHECK(row[1].kind() == SampleValue::Kind::null);
    CHECK(driver->link().state == MachineLink::disconnected);
    CHECK(driver->link().reason == "E-stop");
    WriteRequest w;
    w.id = "p1";
    w.new_value = "text";
    auto bad = driver->write(w);
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::value_type);
    NoopControl control;
    auto ret = driver->run_method(PointRef{"m1"}, Json{{"a", 1}}, control);
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
        CHECK_THAT(r.error().message, Catch::Contains("driver ABI version 999 is not supported (this nclink loads version 2)"));
        CHECK(r.error().message.find('\n') == std::string::npos);  // one line
    }
    SECTION("ABI version 1 (removed before the first release: no released plugin speaks it)") {
        auto r = load_driver_plugin(plugin("old_abi"));
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().code == ErrorCode::value_type);
        CHECK_THAT(r.error().message, Catch::Contains("driver ABI version 1 is not supported (this nclink loads version 2)"));
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
        CHECK(r.error().code == ErrorCode::unavailable);  // the code create() returned
    }
    SECTION("no such file") {
        auto r = load_driver_plugin("/nonexistent/driver.so");
        REQUIRE_FALSE(r.ok());
        CHECK_THAT(r.error().message, Catch::Contains("driver plugin /nonexistent/driver.so does not exist"));
    }
}
