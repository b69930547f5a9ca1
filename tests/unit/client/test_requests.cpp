// Request/response matching of the client against a scripted adapter on the
// loopback broker: @id matching, mirror topics, timeouts, late and malformed
// responses, DEV_UNREACHABLE, whole-request refusals.
#include "fake_adapter.hpp"

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

using namespace nclink;
using namespace std::chrono_literals;
using nclink::test::eventually;
using nclink::test::FakeAdapter;
using nclink::test::make_client;
using nclink::test::reply_to;

namespace {

std::vector<QueryItem> items(std::initializer_list<const char*> ids) {
    std::vector<QueryItem> out;
    for (const char* id : ids) out.push_back(QueryItem{id, std::nullopt});
    return out;
}

}  // namespace

TEST_CASE("a query goes to Query/Request/{dev}/{ex} and is answered on the mirror topic") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");

    auto result = client->query("dev1", items({"0101", "0102"}));
    REQUIRE(result.ok());
    REQUIRE(result->size() == 2);
    CHECK((*result)[0].id == "0101");
    CHECK((*result)[0].status.ok);
    CHECK(*(*result)[0].values == Json::array({"v-0101"}));
    CHECK((*result)[1].id == "0102");

    const auto requests = adapter.requests();
    REQUIRE(requests.size() == 1);
    CHECK(requests[0].topic == "Query/Request/dev1/app1");
    CHECK(requests[0].qos == 1);
    const Json sent = Json::parse(requests[0].payload);
    CHECK(sent["guid"] == "dev1");
    REQUIRE(sent["@id"].is_string());
    CHECK(sent["@id"].get<std::string>().rfind("app1-", 0) == 0);
    CHECK(client->stats().responses == 1);
}

TEST_CASE("concurrent requests are matched by @id even when answered out of order") {
    LoopbackBroker broker;
    // Holds requests until it has 8, then answers them newest first.
    std::mutex mutex;
    std::vector<Message> held;
    FakeAdapter adapter(broker, "dev1", [&](const Message& m) {
        std::lock_guard<std::mutex> lock(mutex);
        held.push_back(m);
        std::vector<Message> out;
        if (held.size() < 8) return out;
        for (auto it = held.rbegin(); it != held.rend(); ++it) {
            auto replies = test::echo_script(*it, "dev1");
            out.insert(out.end(), replies.begin(), replies.end());
        }
        held.clear();
        return out;
    });
    auto client = make_client(broker, "app1");

    std::vector<std::future<Result<std::vector<QueryResult>>>> futures;
    for (int i = 0; i < 8; ++i) {
        const std::string id = "item" + std::to_string(i);
        futures.push_back(std::async(std::launch::async, [&client, id] {
            return client->query("dev1", {QueryItem{id, std::nullopt}});
        }));
    }
    for (int i = 0; i < 8; ++i) {
        auto result = futures[static_cast<std::size_t>(i)].get();
        REQUIRE(result.ok());
        REQUIRE(result->size() == 1);
        CHECK((*result)[0].id == "item" + std::to_string(i));
        CHECK(*(*result)[0].values == Json::array({"v-item" + std::to_string(i)}));
    }
    CHECK(client->stats().responses == 8);
    CHECK(client->pending_requests() == 0);
}

TEST_CASE("async requests complete on the dispatch thread, not the caller's") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");
    std::promise<std::pair<bool, std::thread::id>> where;
    client->query_async("dev1", items({"a"}), [&](Result<std::vector<QueryResult>> r) {
        where.set_value({r.ok(), std::this_thread::get_id()});
    });
    const auto [ok, thread] = where.get_future().get();
    CHECK(ok);
    CHECK(thread != std::this_thread::get_id());
}

TEST_CASE("a silent adapter makes the request time out") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", nullptr);
    auto client = make_client(broker, "app1", 100ms);
    const auto started = std::chrono::steady_clock::now();
    auto result = client->query("dev1", items({"a"}));
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::timeout);
    CHECK(std::chrono::steady_clock::now() - started >= 100ms);
    CHECK(client->stats().timeouts == 1);
    CHECK(client->pending_requests() == 0);

    RequestOptions longer;
    longer.timeout = 50ms;
    auto probe = client->probe("dev1", longer);
    REQUIRE_FALSE(probe.ok());
    CHECK(probe.error().code == ErrorCode::timeout);
}

TEST_CASE("a request to a device whose retained state is offline says so when it times out") {
    LoopbackBroker broker;
    // What a dead adapter leaves behind: its last will, retained.
    LoopbackOptions o;
    o.client_id = "dead-adapter";
    auto dead = make_loopback_transport(broker, o);
    REQUIRE(dead->start().ok());
    REQUIRE(dead->publish(Message{"Notify/State/dev1", R"({"tid":"dev1","state":"offline"})", 1, true}).ok());
    // Publishing is asynchronous: the broker holds it before the adapter dies.
    REQUIRE(eventually([&] { return broker.retained("Notify/State/dev1").has_value(); }));
    dead->stop(0ms);

    auto client = make_client(broker, "app1", 100ms);
    std::atomic<bool> seen{false};
    REQUIRE(client->subscribe_state("dev1", [&](const NotifyState&) { seen = true; }).ok());
    REQUIRE(eventually([&] { return seen.load(); }));
    auto result = client->query("dev1", items({"a"}));
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::timeout);
    INFO(result.error().message);
    CHECK(result.error().message.find("device dev1 is offline") != std::string::npos);
    CHECK(result.error().message.find("retained Notify/State/dev1") != std::string::npos);
}

TEST_CASE("a response after the timeout is dropped and counted") {
    LoopbackBroker broker;
    std::mutex mutex;
    std::vector<Message> held;
    FakeAdapter adapter(broker, "dev1", [&](const Message& m) {
        std::lock_guard<std::mutex> lock(mutex);
        held.push_back(m);
        return std::vector<Message>{};
    });
    auto client = make_client(broker, "app1", 50ms);
    std::atomic<int> calls{0};
    std::promise<Result<std::vector<QueryResult>>> done;
    client->query_async("dev1", items({"a"}), [&](Result<std::vector<QueryResult>> r) {
        ++calls;
        done.set_value(std::move(r));
    });
    auto result = done.get_future().get();
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::timeout);

    std::vector<Message> late;
    {
        std::lock_guard<std::mutex> lock(mutex);
        REQUIRE(held.size() == 1);
        late = test::echo_script(held[0], "dev1");
    }
    adapter.publish(late.at(0));
    REQUIRE(eventually([&] { return client->stats().late_responses == 1; }));
    CHECK(calls == 1);
    CHECK(client->stats().responses == 0);
}

TEST_CASE("responses on the topic without ex or for unknown ids are not taken") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) {
        auto replies = test::echo_script(m, "dev1");
        std::vector<Message> out;
        Message no_ex = replies.at(0);
        no_ex.topic = "Query/Response/dev1";  // not the mirror of .../dev1/app1
        out.push_back(no_ex);
        Message other_id = replies.at(0);
        Json body = Json::parse(other_id.payload);
        body["@id"] = "someone-else-1";
        other_id.payload = body.dump();
        out.push_back(other_id);
        return out;
    });
    auto client = make_client(broker, "app1", 150ms);
    auto result = client->query("dev1", items({"a"}));
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::timeout);
    CHECK(client->stats().unmatched_responses == 1);
}

TEST_CASE("malformed responses are ignored and the good one still completes the request") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) {
        auto good = test::echo_script(m, "dev1").at(0);
        const Json id = Json::parse(m.payload)["@id"];
        std::vector<Message> out;
        out.push_back({good.topic, "not json at all", 1, false});
        out.push_back({good.topic, "[1,2,3]", 1, false});
        out.push_back({good.topic, Json{{"@id", id}, {"values", 5}}.dump(), 1, false});
        out.push_back({good.topic, Json{{"@id", id}, {"values", {{{"id", 7}}}}}.dump(), 1, false});
        out.push_back({good.topic, std::string(5000, '['), 1, false});
        out.push_back(good);
        return out;
    });
    auto client = make_client(broker, "app1");
    auto result = client->query("dev1", items({"a"}));
    REQUIRE(result.ok());
    CHECK((*result)[0].id == "a");
    CHECK(client->stats().malformed == 5);
}

TEST_CASE("DEV_UNREACHABLE from the agent completes the request as unavailable") {
    LoopbackBroker broker;
    FakeAdapter agent(broker, "dev1", [](const Message& m) {
        DevUnreachable dtu;
        dtu.msg_id = Json::parse(m.payload)["@id"];
        dtu.dev_uuid = "dev1";
        dtu.cli_uuid = "app1";
        return std::vector<Message>{{*response_topic(m.topic), encode(dtu), 1, false}};
    });
    auto client = make_client(broker, "app1");
    auto result = client->query("dev1", items({"a"}));
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::unavailable);
    CHECK(result.error().message.find("DEV_UNREACHABLE") != std::string::npos);
    CHECK(client->stats().unreachable == 1);

    auto set = client->set("dev1", {SetItem{"a", Json{{"value", 1}}, std::nullopt, std::nullopt}});
    REQUIRE_FALSE(set.ok());
    CHECK(set.error().code == ErrorCode::unavailable);
}

TEST_CASE("per-item NG results and whole-request refusals") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) {
        const auto kind = parse_topic(m.topic)->kind;
        if (kind == TopicKind::query_request)
            return std::vector<Message>{reply_to(m,
                                                 {{"values",
                                                   {{{"id", "a"}, {"code", "OK"}, {"values", {1}}},
                                                    {{"id", "zz"}, {"code", "NG"}, {"reason", "Node not exists"}, {"error", 401}}}}},
                                                 "dev1")};
        // Set: refused as a whole.
        return std::vector<Message>{
            reply_to(m, {{"results", Json::array()}, {"code", "NG"}, {"reason", "syntax error"}, {"error", 412}}, "dev1")};
    });
    auto client = make_client(broker, "app1");
    auto result = client->query("dev1", items({"a", "zz"}));
    REQUIRE(result.ok());
    REQUIRE(result->size() == 2);
    CHECK((*result)[0].status.ok);
    CHECK_FALSE((*result)[1].status.ok);
    CHECK((*result)[1].status.error == 401);
    CHECK((*result)[1].status.reason == "Node not exists");

    auto set = client->set("dev1", {SetItem{"a", Json{{"value", 1}}, std::nullopt, std::nullopt}});
    REQUIRE_FALSE(set.ok());
    CHECK(set.error().code == ErrorCode::syntax_error);
}

TEST_CASE("probe, probe set and set round trips") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");
    auto model = client->probe("dev1");
    REQUIRE(model.ok());
    CHECK((*model)["id"] == "root");
    CHECK(client->probe_set("dev1", Json{{"id", "root"}}).ok());
    auto set = client->set("dev1", {SetItem{"x", Json{{"value", 3}}, std::nullopt, std::nullopt},
                                    SetItem{"y", Json{{"value", "s"}}, std::nullopt, std::nullopt}});
    REQUIRE(set.ok());
    REQUIRE(set->size() == 2);
    CHECK((*set)[1].id == "y");
    const auto requests = adapter.requests();
    REQUIRE(requests.size() == 3);
    CHECK(requests[0].topic == "Probe/Query/Request/dev1/app1");
    CHECK(requests[1].topic == "Probe/Set/Request/dev1/app1");
    CHECK(Json::parse(requests[1].payload)["probe"]["id"] == "root");
    CHECK(requests[2].topic == "Set/Request/dev1/app1");
}

TEST_CASE("register with an agent answering, refusing, and without one") {
    LoopbackBroker broker;
    auto client = make_client(broker, "app1", 100ms);
    SECTION("no agent: outcome no_answer, not an error") {
        auto outcome = client->register_terminal();
        REQUIRE(outcome.ok());
        CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);
        // The client keeps working.
        FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
        CHECK(client->query("dev1", items({"a"}), RequestOptions{2000ms, std::nullopt}).ok());
    }
    SECTION("agent accepts / refuses") {
        const bool accept = GENERATE(true, false);
        FakeAdapter agent(broker, "agent",
                          [accept](const Message& m) {
                              const Json req = Json::parse(m.payload);
                              RegisterResponse r;
                              r.msg_id = req["@id"];
                              r.cli_uuid = req["cli_uuid"].get<std::string>();
                              if (!accept) r.status = ResponseStatus::failure(ErrorCode::permission_denied);
                              return std::vector<Message>{{topics::register_response(r.cli_uuid), encode(r), 1, false}};
                          },
                          {topics::register_request()});
        auto outcome = client->register_terminal(RequestOptions{2000ms, std::nullopt});
        REQUIRE(outcome.ok());
        CHECK(outcome->kind == (accept ? RegisterOutcome::Kind::accepted : RegisterOutcome::Kind::refused));
        CHECK(outcome->status.ok == accept);
        const auto requests = agent.requests();
        REQUIRE(requests.size() == 1);
        CHECK(requests[0].topic == "Register/Request");
        CHECK(Json::parse(requests[0].payload)["cli_uuid"] == "app1");
    }
}

TEST_CASE("connect starts, waits for the link and registers") {
    LoopbackBroker broker;
    LoopbackOptions o;
    o.client_id = "app1";
    ClientOptions co;
    co.ex_cid = "app1";
    co.default_timeout = 50ms;
    auto client = Client::create(make_loopback_transport(broker, o), co);
    REQUIRE(client.ok());
    CHECK((*client)->state() == ClientState::initial);
    auto outcome = (*client)->connect(5000ms);
    REQUIRE(outcome.ok());
    CHECK(outcome->kind == RegisterOutcome::Kind::no_answer);
    CHECK((*client)->link_state() == LinkState::connected);
    CHECK((*client)->state() == ClientState::normal);
}

TEST_CASE("link state follows the broker and requests wait while it is down") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");
    broker.set_online(false);
    REQUIRE(eventually([&] { return client->state() == ClientState::disconnected; }));
    CHECK(client->link_state() != LinkState::connected);
    std::promise<Result<std::vector<QueryResult>>> done;
    client->query_async(
        "dev1", items({"a"}), [&](auto r) { done.set_value(std::move(r)); }, RequestOptions{5000ms, std::nullopt});
    CHECK(client->pending_requests() == 1);
    broker.set_online(true);
    auto result = done.get_future().get();
    REQUIRE(result.ok());
    CHECK((*result)[0].id == "a");
    REQUIRE(eventually([&] { return client->state() == ClientState::normal; }));
}

TEST_CASE("stop completes pending requests with unavailable and later requests fail at once") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", nullptr);
    auto client = make_client(broker, "app1", 10000ms);
    std::promise<Result<std::vector<QueryResult>>> done;
    client->query_async("dev1", items({"a"}), [&](auto r) { done.set_value(std::move(r)); });
    REQUIRE(eventually([&] { return adapter.request_count() == 1; }));
    client->stop();
    auto result = done.get_future().get();
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::unavailable);
    auto after = client->query("dev1", items({"a"}));
    REQUIRE_FALSE(after.ok());
    CHECK(after.error().code == ErrorCode::unavailable);
}

TEST_CASE("blocking calls from a callback are refused instead of deadlocking") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");
    std::promise<Result<std::vector<QueryResult>>> nested;
    client->query_async("dev1", items({"a"}), [&](auto) { nested.set_value(client->query("dev1", items({"b"}))); });
    auto result = nested.get_future().get();
    REQUIRE_FALSE(result.ok());
    CHECK(result.error().code == ErrorCode::unavailable);
}

TEST_CASE("a throwing callback does not take the client down") {
    LoopbackBroker broker;
    FakeAdapter adapter(broker, "dev1", [](const Message& m) { return test::echo_script(m, "dev1"); });
    auto client = make_client(broker, "app1");
    std::atomic<bool> called{false};
    client->query_async("dev1", items({"a"}), [&](auto) {
        called = true;
        throw std::runtime_error("user bug");
    });
    REQUIRE(eventually([&] { return called.load(); }));
    CHECK(client->query("dev1", items({"b"})).ok());
}

TEST_CASE("create refuses unusable options") {
    LoopbackBroker broker;
    ClientOptions co;
    auto no_ex = Client::create(make_loopback_transport(broker, {"x", {}, {}}), co);
    REQUIRE_FALSE(no_ex.ok());
    CHECK(no_ex.error().code == ErrorCode::parameter_missing);
    co.ex_cid = "a/b";
    auto bad = Client::create(make_loopback_transport(broker, {"x", {}, {}}), co);
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::value_type);
    co.ex_cid = "ok";
    CHECK_FALSE(Client::create(std::unique_ptr<Transport>{}, co).ok());
}
