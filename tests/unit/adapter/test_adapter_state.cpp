// The adapter state machine, row by row (state-machine text items 66-82, and the rows
// nclink adds): every state x event pair of the table is checked here, and
// the rows are checked to drive the adapter in test_adapter_state_driven.cpp.
#include <nclink/adapter_state.hpp>

#include <catch2/catch.hpp>

#include <set>
#include <utility>

using namespace nclink;
using S = AdapterState;
using E = AdapterEvent;

namespace {
constexpr unsigned kAnnounce = action_announce_online | action_register | action_announce_version;

void expect(S from, E event, S to, unsigned actions) {
    INFO(to_string(from) << " + " << to_string(event));
    const auto t = adapter_transition(from, event);
    CHECK(t.next == to);
    CHECK(t.actions == actions);
}
}  // namespace

TEST_CASE("adapter table: every state x event pair has exactly one row, with its source") {
    const auto table = adapter_table();
    REQUIRE(table.size == adapter_state_count * adapter_event_count);
    std::set<std::pair<int, int>> seen;
    for (std::size_t i = 0; i < table.size; ++i) {
        const auto& row = table.rows[i];
        CHECK(seen.insert({static_cast<int>(row.state), static_cast<int>(row.event)}).second);
        CHECK(row.source != nullptr);
        CHECK(std::string(row.source).size() > 0);
        CHECK(to_string(row.state) != "?");
        CHECK(to_string(row.event) != "?");
    }
    CHECK(seen.size() == table.size);
}

TEST_CASE("adapter initial: initialization goes normal (67), nothing else can happen") {
    expect(S::initial, E::initialized, S::normal, action_initialize);
    for (E e : {E::request_handled, E::response_failed, E::link_lost, E::link_restored, E::sample_due, E::model_changed,
                E::retry_due, E::cache_flushed})
        expect(S::initial, e, S::initial, action_none);
}

TEST_CASE("adapter normal state (69-72)") {
    expect(S::normal, E::initialized, S::normal, action_none);
    expect(S::normal, E::request_handled, S::normal, action_send_response);
    expect(S::normal, E::response_failed, S::request, action_cache_response);
    expect(S::normal, E::link_lost, S::disconnected, action_none);
    expect(S::normal, E::link_restored, S::normal, kAnnounce);
    expect(S::normal, E::sample_due, S::normal, action_send_sample);
    expect(S::normal, E::model_changed, S::normal, action_announce_version);
    expect(S::normal, E::retry_due, S::normal, action_none);
    expect(S::normal, E::cache_flushed, S::normal, action_none);
}

TEST_CASE("adapter request state (74-77)") {
    expect(S::request, E::initialized, S::request, action_none);
    expect(S::request, E::request_handled, S::request, action_send_response);
    expect(S::request, E::response_failed, S::request, action_cache_response);
    expect(S::request, E::link_lost, S::disconnected, action_none);
    expect(S::request, E::link_restored, S::normal, kAnnounce | action_flush_cached);
    expect(S::request, E::sample_due, S::request, action_send_sample);
    expect(S::request, E::model_changed, S::request, action_announce_version);
    expect(S::request, E::retry_due, S::request, action_flush_cached);
    expect(S::request, E::cache_flushed, S::normal, action_none);
}

TEST_CASE("adapter disconnected state (79-82)") {
    expect(S::disconnected, E::initialized, S::disconnected, action_none);
    expect(S::disconnected, E::request_handled, S::disconnected, action_cache_response);
    expect(S::disconnected, E::response_failed, S::disconnected, action_cache_response);
    expect(S::disconnected, E::link_lost, S::disconnected, action_none);
    expect(S::disconnected, E::link_restored, S::normal, kAnnounce | action_flush_cached);
    expect(S::disconnected, E::sample_due, S::disconnected, action_send_sample);
    expect(S::disconnected, E::model_changed, S::disconnected, action_none);
    expect(S::disconnected, E::retry_due, S::disconnected, action_none);
    expect(S::disconnected, E::cache_flushed, S::disconnected, action_none);
}

TEST_CASE("adapter state and event names") {
    CHECK(to_string(S::request) == "request");
    CHECK(to_string(E::link_restored) == "link_restored");
    CHECK(to_string(E::model_changed) == "model_changed");
}
