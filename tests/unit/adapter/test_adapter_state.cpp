// The adapter state machine, transition by transition (docs/state-machines.md).
#include <nclink/adapter_state.hpp>

#include <catch2/catch.hpp>

using namespace nclink;
using S = AdapterState;
using E = AdapterEvent;

namespace {
void expect(S from, E event, S to, unsigned actions) {
    INFO(to_string(from) << " + " << to_string(event));
    const auto t = adapter_transition(from, event);
    CHECK(t.next == to);
    CHECK(t.actions == actions);
}
}  // namespace

TEST_CASE("initial: initialization loads the model, registers, goes normal (67)") {
    expect(S::initial, E::initialized, S::normal, action_initialize);
    expect(S::initial, E::request_answered, S::initial, action_none);
    expect(S::initial, E::link_lost, S::initial, action_none);
}

TEST_CASE("normal state (69-72)") {
    expect(S::normal, E::request_answered, S::normal, action_send_response);
    expect(S::normal, E::request_answer_failed, S::request, action_send_response);
    expect(S::normal, E::link_lost, S::disconnected, action_none);
    expect(S::normal, E::link_restored, S::normal, action_none);
    expect(S::normal, E::sample_due, S::normal, action_send_sample);
}

TEST_CASE("request state (74-77)") {
    expect(S::request, E::request_answered, S::request, action_send_response);
    expect(S::request, E::request_answer_failed, S::request, action_send_response);
    expect(S::request, E::link_lost, S::disconnected, action_cache_response);
    expect(S::request, E::link_restored, S::normal, action_flush_cached);
    expect(S::request, E::sample_due, S::request, action_send_sample);
}

TEST_CASE("disconnected state (79-82)") {
    expect(S::disconnected, E::request_answered, S::disconnected, action_cache_response);
    expect(S::disconnected, E::request_answer_failed, S::disconnected, action_cache_response);
    expect(S::disconnected, E::link_lost, S::disconnected, action_none);
    expect(S::disconnected, E::link_restored, S::normal, action_flush_cached);
    expect(S::disconnected, E::sample_due, S::disconnected, action_send_sample);
}

TEST_CASE("state and event names") {
    CHECK(to_string(S::request) == "request");
    CHECK(to_string(E::link_restored) == "link_restored");
}
