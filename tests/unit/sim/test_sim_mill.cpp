// The mill profile: program execution, motion, spindle, methods, alarms.
#include "sim_test_util.hpp"

#include <cmath>
#include <set>
#include <string>

using namespace nclink;
using sim_test::Rig;

namespace {

struct Pos {
    double x, y, z;
};

Pos position(Rig& rig) {
    auto r = rig.read({"x_position", "y_position", "z_position"});
    for (auto& v : r) REQUIRE(v.ok());
    return {r[0].value().get<double>(), r[1].value().get<double>(), r[2].value().get<double>()};
}

double distance(const Pos& a, const Pos& b) {
    return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}

constexpr double rapid_mm_s = 6000.0 / 60.0;  // the fastest the mill moves at 100 %
constexpr double rounding = 0.0025;           // positions are rounded to 1 um per axis

}  // namespace

TEST_CASE("sim-mill.json is recognised as the mill") {
    Rig rig("sim-mill.json");
    CHECK(rig.driver->is_mill());
    CHECK(rig.value("status") == "running");
    CHECK(rig.value("work_mode") == "auto");
    CHECK(rig.value("program") == "O1000");
    CHECK(rig.value("part_count") == "0");
    CHECK(rig.value("feed_override") == 100);
    CHECK(rig.value("warning") == Json::object());
    CHECK(rig.value("emergency_stop") == false);
}

TEST_CASE("axes move continuously, never faster than feed x override") {
    Rig rig("sim-mill.json");
    Pos last = position(rig);
    double travelled = 0;
    std::set<std::string> lines;
    for (int i = 0; i < 12'000; ++i) {  // 120 s in 10 ms steps
        rig.advance_ms(10);
        const Pos p = position(rig);
        const double d = distance(p, last);
        INFO("step " << i);
        REQUIRE(d <= rapid_mm_s * 0.010 + rounding);
        travelled += d;
        last = p;
        if (i % 10 == 0) lines.insert(rig.value("line_number").get<std::string>());
    }
    CHECK(travelled > 500);    // the program really runs
    CHECK(lines.size() > 10);  // and the line number advances
    CHECK(rig.value("tool_number").is_number());

    SECTION("half the feed override halves the top speed") {
        REQUIRE(rig.set("feed_override", Json{{"value", 50}}).ok());
        CHECK(rig.value("feed_override") == 50);
        for (int i = 0; i < 3'000; ++i) {
            rig.advance_ms(10);
            const Pos p = position(rig);
            REQUIRE(distance(p, last) <= rapid_mm_s * 0.5 * 0.010 + rounding);
            last = p;
        }
    }
}

TEST_CASE("speeds and feed follow the motion") {
    Rig rig("sim-mill.json");
    rig.advance_ms(6'000);  // tool change done, first pocket pass under way
    bool moving = false;
    for (int i = 0; i < 200 && !moving; ++i) {
        rig.advance_ms(50);
        moving = rig.value("feed_speed").get<double>() > 0;
    }
    REQUIRE(moving);
    const double fs = rig.value("feed_speed").get<double>() * 60.0;  // mm/min
    const double vx = rig.value("x_speed").get<double>();
    const double vy = rig.value("y_speed").get<double>();
    const double vz = rig.value("z_speed").get<double>();
    CHECK(std::sqrt(vx * vx + vy * vy + vz * vz) == Approx(fs).margin(1.0));
    CHECK(rig.value("spindle_mode") == "forward");
}

TEST_CASE("spindle speed follows S and the spindle override") {
    Rig rig("sim-mill.json");
    rig.advance_ms(10'000);  // S8000 M3 reached
    CHECK(rig.value("spindle_speed") == 8000);
    CHECK(rig.value("spindle_load").get<double>() > 0);
    REQUIRE(rig.set("spindle_override", Json{{"value", 120}}).ok());
    rig.advance_ms(2'000);
    CHECK(rig.value("spindle_speed") == 9600);
    REQUIRE(rig.set("spindle_override", Json{{"value", 150}}).ok());
    rig.advance_ms(2'000);
    CHECK(rig.value("spindle_speed") == 12000);  // the model's UPPER_LIMIT
    auto refused = rig.set("spindle_override", Json{{"value", 151}});
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::out_of_range);
    CHECK(rig.value("spindle_override") == 150);
}

TEST_CASE("feed override 0 stops the motion") {
    Rig rig("sim-mill.json");
    rig.advance_ms(8'000);
    REQUIRE(rig.set("feed_override", Json{{"value", 0}}).ok());
    const Pos stopped = position(rig);
    rig.advance_ms(5'000);
    CHECK(distance(position(rig), stopped) == 0);
    CHECK(rig.value("x_speed") == 0);
    CHECK(rig.value("feed_speed") == 0);
    CHECK(rig.value("status") == "running");
    REQUIRE(rig.set("feed_override", Json{{"value", 100}}).ok());
    rig.advance_ms(1'000);
    CHECK(distance(position(rig), stopped) > 0);
}

TEST_CASE("feed hold, cycle start and reset change the status") {
    Rig rig("sim-mill.json");
    rig.advance_ms(8'000);

    auto held = rig.call("feed_hold");
    REQUIRE(held.ok());
    CHECK(held.value()["status"] == "holding");
    CHECK(rig.value("status") == "holding");
    const Pos at_hold = position(rig);
    const Json line_at_hold = rig.value("line_number");
    rig.advance_ms(10'000);
    CHECK(distance(position(rig), at_hold) == 0);
    CHECK(rig.value("y_speed") == 0);
    CHECK(rig.value("line_number") == line_at_hold);

    REQUIRE(rig.call("cycle_start").ok());
    CHECK(rig.value("status") == "running");
    rig.advance_ms(2'000);
    CHECK(distance(position(rig), at_hold) > 0);

    auto reset = rig.call("reset");
    REQUIRE(reset.ok());
    CHECK(reset.value()["status"] == "free");
    CHECK(rig.value("status") == "free");
    CHECK(rig.value("line_number") == "0");
    const Pos at_reset = position(rig);
    rig.advance_ms(5'000);
    CHECK(distance(position(rig), at_reset) == 0);
    CHECK(rig.value("spindle_mode") == "stop");
    CHECK(rig.value("spindle_speed") == 0);

    REQUIRE(rig.call("cycle_start").ok());
    rig.advance_ms(100);
    CHECK(rig.value("line_number") != "0");
}

TEST_CASE("the mill can start free") {
    Rig rig("sim-mill.json", 1, false);
    CHECK(rig.value("status") == "free");
    const Pos p = position(rig);
    rig.advance_ms(10'000);
    CHECK(distance(position(rig), p) == 0);
    REQUIRE(rig.call("cycle_start").ok());
    rig.advance_ms(10'000);
    CHECK(distance(position(rig), p) > 0);
}

TEST_CASE("program_transfer without a program directory is unavailable and unknown methods do not exist") {
    Rig rig("sim-mill.json");
    auto r = rig.call("program_transfer");
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::unavailable);
    auto missing = rig.call("self_destruct");
    REQUIRE_FALSE(missing.ok());
    CHECK(missing.error().code == ErrorCode::node_not_exists);
}

TEST_CASE("the part count increments after each program cycle") {
    Rig rig("sim-mill.json");
    int increments = 0;
    std::string last = rig.value("part_count");
    for (int i = 0; i < 400; ++i) {  // 400 s
        rig.advance_ms(1'000);
        const std::string now = rig.value("part_count");
        if (now != last) {
            CHECK(std::stoi(now) == std::stoi(last) + 1);
            ++increments;
            last = now;
        }
    }
    CHECK(increments >= 2);
    // Operators reset the counter.
    REQUIRE(rig.set("part_count", Json{{"value", "100"}}).ok());
    CHECK(rig.value("part_count") == "100");
}

TEST_CASE("alarms are raised and cleared") {
    Rig rig("sim-mill.json");
    rig.advance_ms(8'000);
    rig.driver->raise_alarm("2010", "spindle overload");
    const Json w = rig.value("warning");
    CHECK(w["number"] == "2010");
    CHECK(w["text"] == "spindle overload");
    CHECK(w["emerge_time"] == rig.clock->wall_ms());
    CHECK(rig.value("status") == "holding");  // an alarm holds the feed

    rig.driver->clear_alarm("2010");
    CHECK(rig.value("warning") == Json::object());

    // Set raises and clears too.
    REQUIRE(rig.set("warning", Json{{"value", {{"number", "3005"}, {"text", "coolant level low"}}}}).ok());
    CHECK(rig.value("warning")["number"] == "3005");
    CHECK(rig.value("warning")["emerge_time"].is_number());
    REQUIRE(rig.set("warning", Json{{"value", Json::object()}}).ok());
    CHECK(rig.value("warning") == Json::object());

    // Reset clears every alarm.
    rig.driver->raise_alarm("1001", "X axis following error too large");
    REQUIRE(rig.call("reset").ok());
    CHECK(rig.value("warning") == Json::object());
}

TEST_CASE("emergency stop stops the mill until released") {
    Rig rig("sim-mill.json");
    rig.advance_ms(5'000);
    REQUIRE(rig.set("emergency_stop", Json{{"value", true}}).ok());
    CHECK(rig.value("status") == "free");
    CHECK(rig.value("warning")["number"] == "9000");
    auto refused = rig.call("cycle_start");
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().code == ErrorCode::permission_denied);
    REQUIRE(rig.set("emergency_stop", Json{{"value", false}}).ok());
    REQUIRE(rig.call("reset").ok());
    REQUIRE(rig.call("cycle_start").ok());
    CHECK(rig.value("status") == "running");
}

TEST_CASE("status and work mode accept Set") {
    Rig rig("sim-mill.json");
    REQUIRE(rig.set("status", Json{{"value", "holding"}}).ok());
    CHECK(rig.value("status") == "holding");
    auto bad = rig.set("status", Json{{"value", "exploded"}});
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::out_of_range);
    CHECK(rig.value("status") == "holding");
    REQUIRE(rig.set("work_mode", Json{{"value", "manual"}}).ok());
    CHECK(rig.value("status") == "free");
    CHECK(rig.call("cycle_start").error().code == ErrorCode::permission_denied);
    REQUIRE(rig.set("work_mode", Json{{"value", "auto"}}).ok());
    REQUIRE(rig.set("status", Json{{"value", "running"}}).ok());
    CHECK(rig.value("status") == "running");
}
