// The window of recent request @ids (src/adapter/dedup_window.hpp): a repeat
// within the window is dropped, one after it or past the capacity is not,
// and the key keeps apart what JSON keeps apart.
#include "adapter/dedup_window.hpp"

#include <catch2/catch.hpp>

#include <memory>
#include <set>
#include <string>
#include <vector>

using nclink::Json;
using nclink::adapter_detail::DedupWindow;

TEST_CASE("dedup window: a repeat within the window is dropped, after it or past the capacity it is new") {
    auto clock = std::make_shared<nclink::ManualClock>();
    DedupWindow window(std::chrono::milliseconds(1000), 3, clock);
    CHECK(window.first_sighting("a"));
    CHECK_FALSE(window.first_sighting("a"));
    clock->advance(std::chrono::milliseconds(999));
    CHECK_FALSE(window.first_sighting("a"));
    clock->advance(std::chrono::milliseconds(1));
    CHECK(window.first_sighting("a"));  // the window has passed
    CHECK(window.first_sighting("b"));
    CHECK(window.first_sighting("c"));
    CHECK(window.first_sighting("d"));  // "a" forgotten: at most 3 kept
    CHECK(window.first_sighting("a"));
    CHECK_FALSE(window.first_sighting("d"));
    // Many keys through a small window: none is lost or kept too long.
    for (int i = 0; i < 10000; ++i) REQUIRE(window.first_sighting("k" + std::to_string(i)));
    CHECK_FALSE(window.first_sighting("k9999"));
    CHECK(window.first_sighting("k9996"));
}

TEST_CASE("dedup key: kind, application and @id, a string @id never meets a number or another string") {
    const std::vector<Json> ids = {Json("1"), Json(1),         Json(1.0),    Json("\"1\""), Json("a|b"),
                                   Json("a"), Json(true),      Json("true"), Json(nullptr), Json("null"),
                                   Json(""),  Json("\\u0041"), Json("A"),    Json(-1),      Json(1.5)};
    std::set<std::string> keys;
    for (const Json& id : ids) keys.insert(DedupWindow::key("query_request", "app1", id));
    CHECK(keys.size() == ids.size());
    CHECK(DedupWindow::key("query_request", "app1", Json("x")) != DedupWindow::key("set_request", "app1", Json("x")));
    CHECK(DedupWindow::key("query_request", "app1", Json("x")) != DedupWindow::key("query_request", "app2", Json("x")));
    CHECK(DedupWindow::key("query_request", "app1", Json("x")) == DedupWindow::key("query_request", "app1", Json("x")));
    // Where the ex ends is not read from its bytes.
    CHECK(DedupWindow::key("query_request", "x|\"y", Json("z")) != DedupWindow::key("query_request", "x", Json("y|\"z")));
}
