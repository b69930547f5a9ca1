// Bounded request intake (src/adapter/request_gate.hpp): requests beyond
// max_pending_requests are shed and counted, payloads beyond
// max_request_bytes are answered 404 unread, and the adapter serves again
// once the backlog is gone.
#include "adapter/request_gate.hpp"
#include "support/adapter_fixture.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

using namespace nclink;
using namespace nclink::test;
using namespace std::chrono_literals;

TEST_CASE("request gate: admits up to its bound, sheds beyond, releases with the last ticket") {
    auto gate = std::make_shared<adapter_detail::RequestGate>(2, 100, Logger{});
    auto a = gate->admit(10);
    auto b = gate->admit(10);
    CHECK(a.verdict == adapter_detail::RequestGate::Verdict::admitted);
    CHECK(b.verdict == adapter_detail::RequestGate::Verdict::admitted);
    CHECK(gate->pending() == 2);
    CHECK(gate->admit(10).verdict == adapter_detail::RequestGate::Verdict::shed);
    CHECK(gate->shed() == 1);
    CHECK(gate->admit(101).verdict == adapter_detail::RequestGate::Verdict::oversized);
    CHECK(gate->oversized() == 1);
    auto copy = a.ticket;  // a request answered by two tasks holds one slot
    a.ticket.reset();
    CHECK(gate->pending() == 2);
    copy.reset();
    CHECK(gate->pending() == 1);
    CHECK(gate->admit(10).verdict == adapter_detail::RequestGate::Verdict::admitted);  // the ticket is dropped at once
    CHECK(gate->pending() == 1);
}

TEST_CASE("requests beyond max_pending_requests are shed and counted while the driver is busy") {
    AdapterConfig c;
    c.max_pending_requests = 4;
    c.driver_timeout = 5000ms;
    AdapterFixture f(c);
    f.driver->delay = 1000ms;
    for (int i = 0; i < 20; ++i)
        f.app->send(topics::query_request("test-dev", "app"), Json{{"@id", "burst-" + std::to_string(i)}, {"ids", {"pos"}}}.dump());
    std::size_t most_pending = 0;
    REQUIRE(eventually(
        [&] {
            most_pending = std::max(most_pending, f.adapter->stats().pending_requests);
            return f.adapter->stats().shed + f.app->on(topics::query_response("test-dev", "app")).size() == 20;
        },
        30s));
    f.driver->delay = 0ms;
    const auto shed = f.adapter->stats().shed;
    CHECK(shed >= 10);         // 20 arrive while the first reads for a second
    CHECK(most_pending <= 4);  // the bound held
    // Every request that was not shed was answered; the adapter serves again.
    CHECK(f.adapter->stats().pending_requests == 0);
    CHECK(f.query(Json::array({Json{{"id", "pos"}}}))["values"][0]["code"] == "OK");
    CHECK(to_json(f.adapter->stats())["shed"] == shed);
    CHECK(to_json(f.adapter->stats())["drops"]["requests_shed"] == shed);  // a loss by cause (nclink stats "drops")
}

TEST_CASE("the housekeeping names shed requests as a loss, read from the counters the statistics show") {
    // The once-a-second drop check reads the counters directly (not the
    // whole statistics); its warning must carry what stats' "drops" says.
    auto lines = std::make_shared<std::vector<std::string>>();
    auto lines_mutex = std::make_shared<std::mutex>();
    AdapterConfig c;
    c.max_pending_requests = 2;
    c.driver_timeout = 5000ms;
    AdapterFixture f(c, false);
    f.logger = Logger(
        [lines, lines_mutex](LogLevel level, std::string_view text) {
            if (level < LogLevel::info) return;
            std::lock_guard<std::mutex> lock(*lines_mutex);
            lines->emplace_back(text);
        },
        LogLevel::info);
    f.start();
    f.driver->delay = 1000ms;
    for (int i = 0; i < 10; ++i)
        f.app->send(topics::query_request("test-dev", "app"), Json{{"@id", "b" + std::to_string(i)}, {"ids", {"pos"}}}.dump());
    REQUIRE(eventually(
        [&] { return f.adapter->stats().shed + f.app->on(topics::query_response("test-dev", "app")).size() == 10; }, 30s));
    const auto shed = f.adapter->stats().shed;
    REQUIRE(shed > 0);
    REQUIRE(to_json(f.adapter->stats())["drops"]["requests_shed"] == shed);
    // The burst's closing line (a second with no growth) carries the total.
    const std::string expected = " in this burst, " + std::to_string(shed) + " in all";
    CHECK(eventually(
        [&] {
            std::lock_guard<std::mutex> lock(*lines_mutex);
            return std::any_of(lines->begin(), lines->end(), [&](const std::string& l) {
                return l.find("drops (requests_shed) stopped") != std::string::npos && l.find(expected) != std::string::npos;
            });
        },
        10s));
    std::lock_guard<std::mutex> lock(*lines_mutex);
    CHECK(std::any_of(lines->begin(), lines->end(),
                      [](const std::string& l) { return l.find("dropping (requests_shed)") != std::string::npos; }));
}

TEST_CASE("a request larger than max_request_bytes is answered 404 unread") {
    AdapterConfig c;
    c.max_request_bytes = 1000;
    AdapterFixture f(c);
    Json ids = Json::array();
    for (int i = 0; i < 200; ++i) ids.push_back("pos");
    const Json big = f.app->request(topics::query_request("test-dev", "app"), topics::query_response("test-dev", "app"),
                                    Json{{"@id", "big"}, {"ids", ids}});
    CHECK(big["code"] == "NG");
    CHECK(big["error"] == 404);
    CHECK(f.adapter->stats().oversized == 1);
    CHECK(f.query(Json::array({Json{{"id", "pos"}}}))["values"][0]["code"] == "OK");
}
