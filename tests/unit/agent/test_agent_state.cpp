// The agent state machine (state-machine text items 28-63): every row of the table,
// its agreement with the state derived from who is online, and the rows
// driving the agent (a request held for an unreachable adapter, a response
// held for an offline application).
#include "agent_fixture.hpp"

#include <nclink/agent_state.hpp>

#include <set>

using namespace nclink;
using namespace nclink::test;
using S = AgentState;
using E = AgentEvent;

namespace {
void expect(S from, E event, S to, unsigned actions) {
    INFO(to_string(from) << " + " << to_string(event));
    const auto t = agent_transition(from, event);
    CHECK(t.next == to);
    CHECK(t.actions == actions);
}
}  // namespace

TEST_CASE("agent table: every state x event pair has exactly one row, with its source") {
    const auto table = agent_table();
    REQUIRE(table.size == agent_state_count * agent_event_count);
    std::set<std::pair<int, int>> seen;
    for (std::size_t i = 0; i < table.size; ++i) {
        CHECK(seen.insert({static_cast<int>(table.rows[i].state), static_cast<int>(table.rows[i].event)}).second);
        CHECK(std::string(table.rows[i].source).size() > 0);
        CHECK(to_string(table.rows[i].state) != "?");
        CHECK(to_string(table.rows[i].event) != "?");
    }
}

TEST_CASE("agent table: initial (31)") {
    expect(S::initial, E::initialized, S::normal, agent_action_check_registrations);
    for (E e : {E::request_received, E::response_received, E::application_lost, E::application_restored, E::adapter_lost,
                E::adapter_restored, E::sample_received})
        expect(S::initial, e, S::initial, agent_action_none);
}

TEST_CASE("agent table: normal (33-39)") {
    expect(S::normal, E::initialized, S::normal, agent_action_none);
    expect(S::normal, E::request_received, S::normal, agent_action_forward_request);
    expect(S::normal, E::response_received, S::normal, agent_action_forward_response);
    expect(S::normal, E::application_lost, S::application_down, agent_action_none);
    expect(S::normal, E::application_restored, S::normal, agent_action_none);
    expect(S::normal, E::adapter_lost, S::adapter_down, agent_action_none);
    expect(S::normal, E::adapter_restored, S::normal, agent_action_none);
    expect(S::normal, E::sample_received, S::normal, agent_action_forward_sample);
}

TEST_CASE("agent table: application down (41-47)") {
    expect(S::application_down, E::initialized, S::application_down, agent_action_none);
    expect(S::application_down, E::request_received, S::application_down, agent_action_forward_request);
    expect(S::application_down, E::response_received, S::application_down, agent_action_hold_response);
    expect(S::application_down, E::application_lost, S::application_down, agent_action_none);
    expect(S::application_down, E::application_restored, S::normal, agent_action_none);
    expect(S::application_down, E::adapter_lost, S::both_down, agent_action_none);
    expect(S::application_down, E::adapter_restored, S::application_down, agent_action_none);
    expect(S::application_down, E::sample_received, S::application_down, agent_action_hold_sample);
}

TEST_CASE("agent table: adapter down (49-55)") {
    expect(S::adapter_down, E::initialized, S::adapter_down, agent_action_none);
    expect(S::adapter_down, E::request_received, S::adapter_down, agent_action_hold_request);
    expect(S::adapter_down, E::response_received, S::adapter_down, agent_action_forward_response);
    expect(S::adapter_down, E::application_lost, S::both_down, agent_action_none);
    expect(S::adapter_down, E::application_restored, S::adapter_down, agent_action_none);
    expect(S::adapter_down, E::adapter_lost, S::both_down, agent_action_none);
    expect(S::adapter_down, E::adapter_restored, S::normal, agent_action_none);
    expect(S::adapter_down, E::sample_received, S::adapter_down, agent_action_forward_sample);
}

TEST_CASE("agent table: both down (57-63)") {
    expect(S::both_down, E::initialized, S::both_down, agent_action_none);
    expect(S::both_down, E::request_received, S::both_down, agent_action_hold_request);
    expect(S::both_down, E::response_received, S::both_down, agent_action_hold_response);
    expect(S::both_down, E::application_lost, S::both_down, agent_action_none);
    expect(S::both_down, E::application_restored, S::adapter_down, agent_action_none);
    expect(S::both_down, E::adapter_lost, S::both_down, agent_action_none);
    expect(S::both_down, E::adapter_restored, S::application_down, agent_action_none);
    expect(S::both_down, E::sample_received, S::both_down, agent_action_forward_sample);
}

TEST_CASE("agent table: a link row lands where the state derived from presence is") {
    // The agent derives each pair's state from who is online; the rows of
    // the link events must agree with that derivation (except 53: the text
    // moves an adapter_down pair to both_down on a second adapter loss).
    for (bool app : {true, false})
        for (bool adapter : {true, false}) {
            const S from = agent_state_of(app, adapter);
            INFO(to_string(from));
            const bool lost_agrees = agent_transition(from, E::application_lost).next == agent_state_of(false, adapter);
            CHECK(lost_agrees);
            CHECK(agent_transition(from, E::application_restored).next == agent_state_of(true, adapter));
            if (from != S::adapter_down) CHECK(agent_transition(from, E::adapter_lost).next == agent_state_of(app, false));
            CHECK(agent_transition(from, E::adapter_restored).next == agent_state_of(app, true));
        }
}

TEST_CASE("agent driven: stats name the state, a response for an offline application is held (42)") {
    AgentFixture f;
    CHECK(f.agent->stats().state == "normal");
    auto mill = f.peer("mill-1", offline_will("mill-1"));
    f.announce(*mill, "mill-1");
    f.announce(*f.app, "mes", "offline");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mes") == "offline"; }));
    mill->send(topics::query_response("mill-1", "mes"), Json{{"@id", "q1"}, {"code", "OK"}, {"values", Json::array()}}.dump());
    REQUIRE(eventually([&] { return f.agent->stats().held_responses == 1; }));
    f.announce(*f.app, "mes", "online");
    REQUIRE(eventually([&] { return status_of(*f.agent, "mes") == "online"; }));
    mill->send(topics::query_response("mill-1", "mes"), Json{{"@id", "q2"}, {"code", "OK"}, {"values", Json::array()}}.dump());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    CHECK(f.agent->stats().held_responses == 1);
}
