// Set on simulated items: single, list and dict, all or nothing.
#include "sim_test_util.hpp"

using namespace nclink;
using sim_test::Rig;

TEST_CASE("Set on list elements is visible on the next read") {
    Rig rig("sim-mill.json");
    Json tool = rig.value("tools")[3];
    tool["radius"] = 6.0;
    REQUIRE(rig.set("tools", Json{{"index", 3}, {"value", tool}}).ok());
    rig.advance_ms(1'000);
    const Json tools = rig.value("tools");
    CHECK(tools[3]["radius"] == 6.0);
    CHECK(tools.size() == 64);

    // G54 of the coordinate systems.
    REQUIRE(rig.set("coordinates", Json{{"index", "0"}, {"value", {{"name", "G54"}, {"x", -1.5}, {"y", -2.5}, {"z", -3.5}}}}).ok());
    CHECK(rig.value("coordinates")[0]["x"] == -1.5);

    // add and delete change the length.
    REQUIRE(rig.set("tools", Json{{"operation", "delete"}, {"index", "60-63"}}).ok());
    CHECK(rig.value("tools").size() == 60);
}

TEST_CASE("A generated table reads the same every time until a Set changes it") {
    // The simulator builds a list/dict it was not given again at each read
    // (drivers/sim/sim_driver.cpp, build()): every read must still see the
    // one table of this machine, and a Set must stick.
    Rig rig("sim-mill.json", 7);
    const Json first = rig.value("tools");
    REQUIRE(first.size() == 64);
    rig.advance_ms(120'000);
    CHECK(rig.value("tools") == first);
    CHECK(rig.value("parameters") == rig.value("parameters"));
    Rig other("sim-mill.json", 8);
    CHECK(other.value("tools") != first);

    Json tool = first[0];
    tool["length"] = 99.5;
    REQUIRE(rig.set("tools", Json{{"index", 0}, {"value", tool}}).ok());
    rig.advance_ms(60'000);
    CHECK(rig.value("tools")[0]["length"] == 99.5);
    CHECK(rig.value("tools")[1] == first[1]);
}

TEST_CASE("Set on dict keys is visible on the next read") {
    Rig rig("sim-mill.json");
    REQUIRE(rig.set("parameters", Json{{"keys", {"P0001", "P0002"}}, {"values", {42, 43.5}}}).ok());
    const Json p = rig.value("parameters");
    CHECK(p["P0001"] == 42);
    CHECK(p["P0002"] == 43.5);
    REQUIRE(rig.set("parameters", Json{{"operation", "add"}, {"key", "P9999"}, {"value", 1}}).ok());
    CHECK(rig.value("parameters").size() == 65);
}

TEST_CASE("Set on single items holds the value") {
    Rig rig("appendix-b.json");
    // A drifting position written by a Set stays where it was put.
    REQUIRE(rig.set("0103080402", Json{{"value", 12.5}}).ok());
    rig.advance_ms(30'000);
    CHECK(rig.value("0103080402") == 12.5);
    // A counter continues from the written value.
    REQUIRE(rig.set("010307", Json{{"value", "500"}}).ok());
    CHECK(rig.value("010307") == "500");
    rig.advance_ms(600'000);
    CHECK(std::stoi(rig.value("010307").get<std::string>()) > 500);
    // Appendix B's settable TOOL list.
    REQUIRE(rig.set("01031207", Json{{"index", 0}, {"value", {{"id", "T01"}}}}).ok());
    CHECK(rig.value("01031207")[0] == Json{{"id", "T01"}});
    // The driver takes the whole new value when no params are given.
    WriteRequest w;
    w.id = "010305";
    w.new_value = 80;
    REQUIRE(rig.driver->write(w).ok());
    CHECK(rig.value("010305") == 80);
}

TEST_CASE("an invalid Set answers the table-19 error and changes nothing") {
    Rig rig("sim-mill.json");
    const Json tools = rig.value("tools");

    auto beyond = rig.set("tools", Json{{"index", 64}, {"value", tools[0]}});
    REQUIRE_FALSE(beyond.ok());
    CHECK(beyond.error().code == ErrorCode::out_of_range);

    // One good and one bad index: neither is written.
    auto mixed = rig.set("tools", Json{{"indexes", {"0", "100"}}, {"value", Json{{"id", "X"}}}});
    REQUIRE_FALSE(mixed.ok());
    CHECK(mixed.error().code == ErrorCode::out_of_range);
    CHECK(rig.value("tools") == tools);

    auto wrong_type = rig.set("tools", Json{{"index", 1}, {"value", 5}});
    REQUIRE_FALSE(wrong_type.ok());
    CHECK(wrong_type.error().code == ErrorCode::value_type);
    CHECK(rig.value("tools") == tools);

    auto no_value = rig.set("feed_override", Json::object());
    REQUIRE_FALSE(no_value.ok());
    CHECK(no_value.error().code == ErrorCode::parameter_missing);

    auto not_number = rig.set("feed_override", Json{{"value", "fast"}});
    REQUIRE_FALSE(not_number.ok());
    CHECK(not_number.error().code == ErrorCode::value_type);
    auto too_much = rig.set("feed_override", Json{{"value", 400}});
    REQUIRE_FALSE(too_much.ok());
    CHECK(too_much.error().code == ErrorCode::out_of_range);
    CHECK(rig.value("feed_override") == 100);

    const Json params = rig.value("parameters");
    auto missing_key = rig.set("parameters", Json{{"keys", {"P0001", "nope"}}, {"values", {1, 2}}});
    REQUIRE_FALSE(missing_key.ok());
    CHECK(rig.value("parameters") == params);
}
