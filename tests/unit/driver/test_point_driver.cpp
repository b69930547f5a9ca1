// PointDriver: declared points answer reads and Sets; range and enumeration
// checks refuse bad Sets before the setter runs; undeclared ids and throwing
// getters answer 202 for their item only.
#include <nclink/point_driver.hpp>

#include <catch2/catch.hpp>

#include <atomic>
#include <stdexcept>
#include <thread>

using namespace nclink;

namespace {

std::vector<Result<Json>> read(Driver& d, std::vector<std::string> ids) {
    std::vector<PointRef> points;
    for (auto& id : ids) points.push_back(PointRef{id, DataKind::single});
    std::vector<Result<Json>> results(points.size(), make_error(ErrorCode::unavailable, "unread"));
    d.read(points, results);
    return results;
}

WriteRequest set(const std::string& id, Json value) {
    WriteRequest w;
    w.id = id;
    w.new_value = std::move(value);
    return w;
}

}  // namespace

TEST_CASE("declared getters, setters and values answer reads and writes") {
    double x = 12.5;
    int override_percent = 100;
    PointDriver d({"lathe", "1"});
    d.point("x", [&] { return x; });
    d.point(
         "ovr", [&] { return override_percent; },
         [&](const Json& v) {
             override_percent = v.get<int>();
             return ok_result();
         })
        .range(50, 120);
    PointValue mode = d.value("mode", "auto", true).one_of({"manual", "auto"});
    d.point("fails", []() -> Result<Json> { return make_error(ErrorCode::unavailable, "machine busy"); });
    d.point("throws", []() -> double { throw std::runtime_error("bus error"); });

    CHECK(d.info().name == "lathe");
    CHECK(d.ids() == std::vector<std::string>{"x", "ovr", "mode", "fails", "throws"});
    auto r = read(d, {"x", "ovr", "mode", "unknown", "fails", "throws"});
    CHECK(*r[0] == 12.5);
    CHECK(*r[1] == 100);
    CHECK(*r[2] == "auto");
    REQUIRE_FALSE(r[3].ok());
    CHECK(r[3].error().code == ErrorCode::unavailable);
    CHECK(r[3].error().message == "driver 'lathe' declares no point 'unknown'");
    CHECK(r[4].error().message == "machine busy");
    CHECK(r[5].error().message == "reading throws failed: bus error");

    x = -3;
    CHECK(*read(d, {"x"})[0] == -3.0);
    mode.set("manual");
    CHECK(*read(d, {"mode"})[0] == "manual");

    REQUIRE(d.write(set("ovr", 110)).ok());
    CHECK(override_percent == 110);
    REQUIRE(d.write(set("mode", "auto")).ok());
    CHECK(mode.get() == "auto");
}

TEST_CASE("range and enumeration checks refuse a Set before the setter runs") {
    int calls = 0;
    PointDriver d;
    d.point(
         "ovr", [] { return 100; },
         [&](const Json&) {
             ++calls;
             return ok_result();
         })
        .range(50, 120);
    d.value("mode", "auto", true).one_of({"manual", "auto"});
    d.point("ro", [] { return 1; });

    auto high = d.write(set("ovr", 150));
    REQUIRE_FALSE(high.ok());
    CHECK(high.error().code == ErrorCode::out_of_range);
    CHECK(high.error().message == "ovr = 150 is outside [50, 120]");
    auto text = d.write(set("ovr", "fast"));
    REQUIRE_FALSE(text.ok());
    CHECK(text.error().code == ErrorCode::value_type);
    auto word = d.write(set("mode", "turbo"));
    REQUIRE_FALSE(word.ok());
    CHECK(word.error().code == ErrorCode::out_of_range);
    CHECK(word.error().message == R"(mode = "turbo" is not one of "manual", "auto")");
    CHECK(calls == 0);

    auto ro = d.write(set("ro", 2));
    REQUIRE_FALSE(ro.ok());
    CHECK(ro.error().code == ErrorCode::permission_denied);
    CHECK(d.write(set("nothing", 1)).error().code == ErrorCode::unavailable);
    CHECK(d.checks("ovr")->max == 120.0);
    CHECK(d.checks("nothing") == nullptr);
}

TEST_CASE("declared points are claimed, so the SDK asks the driver even for configs") {
    PointDriver d;
    d.value("machine_model", "L-200");
    CHECK(d.claims("machine_model"));
    CHECK_FALSE(d.claims("serial_number"));
}

TEST_CASE("a PointValue is updated by the firmware while the SDK reads it") {
    PointDriver d;
    PointValue count = d.value("count", 0);
    std::atomic<bool> done{false};
    std::thread firmware([&] {
        for (int i = 1; i <= 2000; ++i) count.set(i);
        done = true;
    });
    while (!done) REQUIRE(read(d, {"count"})[0]->is_number());
    firmware.join();
    CHECK(*read(d, {"count"})[0] == 2000);
}

TEST_CASE("bind gives declared points their index as handle, and reads and writes use it") {
    PointDriver d({"lathe", "1"});
    int written = 0;
    d.point("a", [] { return 1; });
    d.point(
        "b", [] { return 2; },
        [&](const Json& v) {
            written = v.get<int>();
            return ok_result();
        });
    std::vector<BindPoint> points(3);
    points[0].id = "b";
    points[1].id = "other";  // not declared: left to a subclass, by id
    points[2].id = "a";
    std::vector<PointHandle> handles(points.size(), no_handle);
    REQUIRE(d.bind(points, handles));
    CHECK(handles == std::vector<PointHandle>{1, no_handle, 0});

    // The handle wins over the id: a read by handle needs no lookup.
    std::vector<PointRef> refs{PointRef{"ignored", DataKind::single, 1}, PointRef{"a", DataKind::single, no_handle}};
    std::vector<Result<Json>> results(refs.size(), make_error(ErrorCode::unavailable, "unread"));
    d.read(refs, results);
    CHECK(*results[0] == 2);
    CHECK(*results[1] == 1);

    WriteRequest w;
    w.id = "ignored";
    w.handle = 1;
    w.new_value = 7;
    REQUIRE(d.write(w));
    CHECK(written == 7);
}
