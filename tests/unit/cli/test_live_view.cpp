// The full-screen view of `nclink top`: rows per point, fitted to any size.
#include "live_view.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::cli;

namespace {

SampleDtu dtu(const std::string& channel, std::vector<Json> data) {
    SampleDtu d;
    d.id = channel;
    d.data = std::move(data);
    return d;
}

std::size_t columns(const std::string& line) { return display_width(line); }

}  // namespace

TEST_CASE("live view: each point shows its latest non-null value and age") {
    LiveView view("mill-1", "tcp://b:1883", {{"ch_fast", {"x_pos", "y_pos"}}});
    CHECK(view.rows() == 2);
    view.apply(dtu("ch_fast", {Json::array({1.5, 2.5, nullptr}), Json::array({nullptr})}), 1000);
    view.apply(dtu("ch_slow", {Json::array({"RUN"})}), 1500);
    const auto lines = view.render(80, 10, 3000);
    REQUIRE(lines.size() == 10);
    CHECK_THAT(lines[0], Catch::Contains("mill-1 on tcp://b:1883"));
    CHECK_THAT(lines[0], Catch::Contains("DTUs 2"));
    CHECK_THAT(lines[1], Catch::StartsWith("CHANNEL"));
    CHECK_THAT(lines[2], Catch::StartsWith("ch_fast        x_pos"));
    CHECK_THAT(lines[2], Catch::Contains("2.5"));
    CHECK_THAT(lines[2], Catch::Contains("2.0s"));
    CHECK_THAT(lines[3], Catch::StartsWith("ch_fast        y_pos"));
    CHECK_THAT(lines[3], Catch::EndsWith("-     "));
    CHECK_THAT(lines[4], Catch::StartsWith("ch_slow        p1"));  // not in the model: numbered
    CHECK_THAT(lines[4], Catch::Contains("\"RUN\""));
    CHECK_THAT(lines[9], Catch::StartsWith("q quit"));
}

TEST_CASE("live view: every line fits any terminal size, and scrolling is clamped") {
    std::map<std::string, std::vector<std::string>> channels;
    for (int i = 0; i < 30; ++i) channels["ch"].push_back("item_" + std::to_string(i));
    LiveView view("mill-1", "tcp://b:1883", channels);
    // An escape sequence, and a wide (CJK) value: "温度" takes 4 columns.
    view.apply(dtu("ch", {Json::array({"a\x1b[2Jvalue"}), Json::array({"\xe6\xb8\xa9\xe5\xba\xa6"})}), 1);
    CHECK(display_width("\xe6\xb8\xa9\xe5\xba\xa6") == 4);
    for (auto [w, h] : {std::pair{80, 24}, {40, 10}, {20, 5}, {200, 60}, {1, 1}}) {
        const auto lines = view.render(w, h, 2);
        REQUIRE(lines.size() == static_cast<std::size_t>(h));
        for (const auto& line : lines) {
            CHECK(columns(line) == static_cast<std::size_t>(w));
            CHECK(line.find('\x1b') == std::string::npos);  // no escape sequence from a value reaches the screen
        }
    }
    view.scroll(1000);
    auto lines = view.render(80, 10, 2);
    CHECK_THAT(lines[8], Catch::Contains("item_29"));
    CHECK_THAT(lines[9], Catch::Contains("rows 24-30 of 30"));
    view.scroll(-1000);
    lines = view.render(80, 10, 2);
    CHECK_THAT(lines[2], Catch::Contains("item_0 "));
}
