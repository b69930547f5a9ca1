// The application state machine (docs/state-machines.md): the pure table,
// transition by transition, and the client following it over the loopback
// (requests queued while disconnected and sent on reconnect).
#include "fake_adapter.hpp"

#include <nclink/client_state.hpp>

#include <atomic>
#include <future>
#include <memory>
#include <thread>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::FakeAdapter;
using nclink::test::make_client;

namespace {

using S = ClientState;
using E = ClientEvent;

void expect(S from, E event, S to, unsigned actions, bool queued = false, bool outstanding = false) {
    INFO(to_string(from) << " + " << to_string(event) << " (queued " << queued << ", outstanding " << outstanding << ")");
    const auto t = client_transition(from, event, queued, outstanding);
    CHECK(to_string(t.next) == to_string(to));
    CHECK(t.actions == actions);
}

std::vector<QueryItem> items(std::initializer_list<const char*> ids) {
    std::vector<QueryItem> out;
    for (const char* id : ids) out.push_back(QueryItem{id, std::nullopt});
    return out;
}

}  // namespace

TEST_CASE("client state table: initial (item 9)") {
    expect(S::initial, E::link_restored, S::normal, client_action_register);
    expect(S::initial, E::link_restored, S::request, client_action_register | client_action_send_queued, true);
    expect(S::initial, E::request_made, S::initial, client_action_queue_request);
    expect(S::initial, E::link_lost, S::initial, client_action_none);
    expect(S::initial, E::sample_received, S::initial, client_action_handle_sample);
    expect(S::initial, E::stray_response, S::initial, client_action_drop_response);
}

TEST_CASE("client state table: normal (items 11-15)") {
    expect(S::normal, E::request_made, S::request, client_action_send_request);     // 11
    expect(S::normal, E::stray_response, S::normal, client_action_drop_response);   // 12
    expect(S::normal, E::link_lost, S::disconnected, client_action_none);           // 13
    expect(S::normal, E::link_restored, S::normal, client_action_none);             // 14
    expect(S::normal, E::sample_received, S::normal, client_action_handle_sample);  // 15
}

TEST_CASE("client state table: request (items 17-21)") {
    expect(S::request, E::request_made, S::request, client_action_send_request);          // 17
    expect(S::request, E::last_response, S::normal, client_action_handle_response);       // 18
    expect(S::request, E::response_received, S::request, client_action_handle_response);  // others still wait
    expect(S::request, E::stray_response, S::request, client_action_drop_response);
    expect(S::request, E::link_lost, S::disconnected, client_action_none);            // 19
    expect(S::request, E::link_restored, S::request, client_action_none);             // 20
    expect(S::request, E::sample_received, S::request, client_action_handle_sample);  // 21
}

TEST_CASE("client state table: disconnected (items 23-27)") {
    expect(S::disconnected, E::request_made, S::disconnected, client_action_queue_request);         // 23
    expect(S::disconnected, E::response_received, S::disconnected, client_action_handle_response);  // 24
    expect(S::disconnected, E::last_response, S::disconnected, client_action_handle_response);      // 24
    expect(S::disconnected, E::link_lost, S::disconnected, client_action_none);                     // 25
    expect(S::disconnected, E::link_restored, S::request, client_action_send_queued, true);         // 26, queued
    expect(S::disconnected, E::link_restored, S::normal, client_action_none);                       // 26, none
    expect(S::disconnected, E::link_restored, S::request, client_action_none, false, true);         // sent before, unanswered
    expect(S::disconnected, E::sample_received, S::disconnected, client_action_handle_sample);      // 27
}

TEST_CASE("client state: initial normal request normal over the loopback") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", nullptr);  // silent: the test answers
    LoopbackOptions o;
    o.client_id = "app1";
    ClientOptions co;
    co.ex_cid = "app1";
    auto made = Client::create(make_loopback_transport(broker, o), co);
    REQUIRE(made.ok());
    auto client = std::move(made).value();
    CHECK(client->state() == ClientState::initial);
    REQUIRE(client->start().ok());
    REQUIRE(client->wait_connected(5s));
    REQUIRE(eventually([&] { return client->state() == ClientState::normal; }));
    std::promise<Result<std::vector<QueryResult>>> first, second;
    client->query_async("dev1", items({"a"}), [&](auto r) { first.set_value(std::move(r)); });
    client->query_async("dev1", items({"b"}), [&](auto r) { second.set_value(std::move(r)); });
    CHECK(client->state() == ClientState::request);
    REQUIRE(eventually([&] { return adapter.request_count() == 2; }));
    adapter.publish(test::reply_to(adapter.requests()[0], {{"values", Json::array()}}, "dev1"));
    REQUIRE(first.get_future().get().ok());
    CHECK(client->state() == ClientState::request);  // b still waits
    adapter.publish(test::reply_to(adapter.requests()[1], {{"values", Json::array()}}, "dev1"));
    REQUIRE(second.get_future().get().ok());
    REQUIRE(eventually([&] { return client->state() == ClientState::normal; }));
}

TEST_CASE("client state: requests made while disconnected are queued and sent in order on reconnect") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1", 10000ms);
    broker.set_online(false);
    REQUIRE(eventually([&] { return client->state() == ClientState::disconnected; }));
    std::promise<Result<std::vector<QueryResult>>> a, b;
    client->query_async("dev1", items({"a"}), [&](auto r) { a.set_value(std::move(r)); });
    client->query_async("dev1", items({"b"}), [&](auto r) { b.set_value(std::move(r)); });
    CHECK(client->state() == ClientState::disconnected);
    CHECK(client->stats().queued == 2);
    CHECK(client->stats().requests == 0);
    CHECK(client->transport().stats().buffered == 0);  // held by the client, not the transport
    broker.set_online(true);
    auto ra = a.get_future().get();
    auto rb = b.get_future().get();
    REQUIRE(ra.ok());
    REQUIRE(rb.ok());
    CHECK((*ra)[0].id == "a");
    const auto seen = adapter.requests();
    REQUIRE(seen.size() == 2);
    CHECK(Json::parse(seen[0].payload)["ids"][0]["id"] == "a");  // in the order they were made
    CHECK(Json::parse(seen[1].payload)["ids"][0]["id"] == "b");
    REQUIRE(eventually([&] { return client->state() == ClientState::normal; }));
}

namespace {

// A query made while disconnected whose first delivery is lost, as when the
// broker restarted and the adapter has not subscribed again yet; the
// adapter answers every repeat. Ready when the lost copy has arrived.
struct LostFirstQuery {
    LoopbackBroker broker;
    std::atomic<int> seen{0};
    FakeAdapter adapter{broker, "dev1", [this](const Message& m) -> std::vector<Message> {
                            if (seen++ == 0) return {};
                            return test::echo_script(m, "dev1");
                        }};
    std::unique_ptr<Client> client = make_client(broker, "app1", 10000ms);
    std::promise<Result<std::vector<QueryResult>>> answer;
    std::future<Result<std::vector<QueryResult>>> future = answer.get_future();

    LostFirstQuery() {
        broker.set_online(false);
        REQUIRE(eventually([&] { return client->state() == ClientState::disconnected; }));
        client->query_async("dev1", items({"a"}), [this](auto r) { answer.set_value(std::move(r)); });
        broker.set_online(true);
        REQUIRE(eventually([&] { return adapter.request_count() == 1; }));
    }
};

}  // namespace

TEST_CASE("client state: a queued request lost on reconnect goes out again when its device announces itself (8.3.6)") {
    LostFirstQuery q;
    auto& adapter = q.adapter;
    auto& client = q.client;
    CHECK(q.future.wait_for(100ms) == std::future_status::timeout);  // lost: nothing comes back by itself
    CHECK(client->stats().resent == 0);

    // Another device announcing itself changes nothing.
    adapter.publish(Message{topics::probe_version("dev2"), R"({"@id":"v0","guid":"dev2","version":"1.0"})", 1, false});
    std::this_thread::sleep_for(50ms);
    CHECK(adapter.request_count() == 1);

    adapter.publish(Message{topics::probe_version("dev1"), R"({"@id":"v1","guid":"dev1","version":"1.0"})", 1, false});
    REQUIRE(q.future.wait_for(5s) == std::future_status::ready);
    auto r = q.future.get();
    REQUIRE(r.ok());
    CHECK((*r)[0].id == "a");
    const auto requests = adapter.requests();
    REQUIRE(requests.size() == 2);
    CHECK(Json::parse(requests[0].payload)["@id"] == Json::parse(requests[1].payload)["@id"]);  // the same request
    CHECK(client->stats().resent == 1);

    // Answered: a later announcement sends nothing again.
    adapter.publish(Message{topics::probe_version("dev1"), R"({"@id":"v2","guid":"dev1","version":"1.0"})", 1, false});
    std::this_thread::sleep_for(100ms);
    CHECK(adapter.request_count() == 2);
    CHECK(client->stats().resent == 1);
}

TEST_CASE("client state: an unanswered request from the reconnect queue is queued again by a second outage") {
    LostFirstQuery q;
    q.broker.set_online(false);
    REQUIRE(eventually([&] { return q.client->state() == ClientState::disconnected; }));
    CHECK(q.client->stats().transport.buffered == 0);
    q.broker.set_online(true);
    REQUIRE(q.future.wait_for(5s) == std::future_status::ready);
    REQUIRE(q.future.get().ok());
    CHECK(q.adapter.request_count() == 2);
}

TEST_CASE("client state: a queued request that times out is failed with 203 and never sent") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");
    broker.set_online(false);
    REQUIRE(eventually([&] { return client->state() == ClientState::disconnected; }));
    auto result =
        client->set("dev1", {SetItem{"ovr", Json{{"value", 1}}, std::nullopt, std::nullopt}}, RequestOptions{50ms, std::nullopt});
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::timeout);
    broker.set_online(true);
    REQUIRE(eventually([&] { return client->state() == ClientState::normal; }));
    std::this_thread::sleep_for(100ms);
    CHECK(adapter.request_count() == 0);  // a stale Set never reaches the machine
}

TEST_CASE("client state: a full queue refuses more requests with 404") {
    LoopbackBroker broker;
    LoopbackOptions o;
    o.client_id = "app1";
    ClientOptions co;
    co.ex_cid = "app1";
    co.max_queued_requests = 1;
    auto client = std::move(Client::create(make_loopback_transport(broker, o), co)).value();
    broker.set_online(false);
    REQUIRE(client->start().ok());  // never connects: initial, requests queue
    client->query_async(
        "dev1", items({"a"}), [](auto) {}, RequestOptions{10000ms, std::nullopt});
    auto second = client->query("dev1", items({"b"}));
    REQUIRE_FALSE(second.ok());
    CHECK(second.error().code == ErrorCode::memory_configured);
    CHECK(client->state() == ClientState::initial);
}

TEST_CASE("discover: the device list of the agent's Discovery/Response") {
    LoopbackBroker broker;
    FakeAdapter agent(broker, "agent",
                      [](const Message& m) -> std::vector<Message> {
                          const Json req = Json::parse(m.payload);
                          Json answer = {
                              {"@id", req["@id"]},
                              {"guid", "app1"},
                              {"code", "OK"},
                              {"deviceList", {{{"guid", "mill-1"}, {"status", "online"}, {"lastAliveTimeStamp", "1611287021"}}}}};
                          return {Message{topics::discovery_response("app1"), answer.dump(), 1, false}};
                      },
                      {topics::discovery_request("+")});
    auto client = make_client(broker, "app1");
    auto list = client->discover();
    REQUIRE(list.ok());
    REQUIRE(list->size() == 1);
    CHECK((*list)[0].guid == "mill-1");
    CHECK((*list)[0].status == "online");
    CHECK((*list)[0].last_alive_time_stamp == "1611287021");
    const Json sent = Json::parse(agent.requests()[0].payload);
    CHECK(sent["guid"] == "app1");
    CHECK(agent.requests()[0].topic == "Discovery/Request/app1");
}

TEST_CASE("discover: deviceList null is an empty list and no agent is a timeout") {
    LoopbackBroker broker;
    {
        FakeAdapter agent(
            broker, "agent",
            [](const Message& m) -> std::vector<Message> {
                const Json answer = {
                    {"@id", Json::parse(m.payload)["@id"]}, {"guid", "app1"}, {"code", "OK"}, {"deviceList", nullptr}};
                return {Message{topics::discovery_response("app1"), answer.dump(), 1, false}};
            },
            {topics::discovery_request("+")});
        auto client = make_client(broker, "app1");
        auto list = client->discover();
        REQUIRE(list.ok());
        CHECK(list->empty());
    }
    auto client = make_client(broker, "app2", 100ms);
    auto none = client->discover();
    REQUIRE_FALSE(none.ok());
    CHECK(none.error().code == ErrorCode::timeout);
}
